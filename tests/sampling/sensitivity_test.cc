// Tests of the Sobol first-order and total indices with bootstrap intervals
// (src/sampling/sensitivity.h): the Ishigami function against its analytic indices, coverage
// of the intervals over independent replicas, a linear model with a grouped input and an
// input without effect, failed evaluations (NaN), a constant output, determinism.
#include "sampling/sensitivity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "core/error.h"
#include "sampling/design.h"

namespace {

using poise::sampling::Design;
using poise::sampling::Estimate;
using poise::sampling::SamplingMethod;
using poise::sampling::SobolResult;
namespace ps = poise::sampling;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using Model = std::function<double(std::span<const double>)>;  // unit-cube point -> output

// Model values on Saltelli's radial design: A and B from independent uniforms (one Monte
// Carlo design of dimension 2 D: A = first D coordinates, B = last D), AB^(g) = A with the
// inputs of group g from B.
struct RadialValues {
  std::vector<double> fA, fB;
  std::vector<std::vector<double>> fAB;

  std::vector<std::span<const double>> ab() const {
    std::vector<std::span<const double>> s;
    for (const auto& v : fAB) s.emplace_back(v);
    return s;
  }
  SobolResult indices(std::uint64_t seed, std::size_t resamples = 1000) const {
    return ps::sobol_indices(fA, fB, ab(), seed, resamples);
  }
};

RadialValues evaluate(const Model& f, std::size_t dim, const std::vector<std::vector<std::size_t>>& groups,
                      std::size_t n, std::uint64_t seed) {
  const Design design(SamplingMethod::kMonteCarlo, seed, n, 2 * dim);
  RadialValues out;
  out.fA.resize(n);
  out.fB.resize(n);
  out.fAB.assign(groups.size(), std::vector<double>(n));
  std::vector<double> u(2 * dim), ab(dim);
  for (std::size_t j = 0; j < n; ++j) {
    design.point(j, u);
    const std::span<const double> a(u.data(), dim), b(u.data() + dim, dim);
    out.fA[j] = f(a);
    out.fB[j] = f(b);
    for (std::size_t g = 0; g < groups.size(); ++g) {
      std::copy(a.begin(), a.end(), ab.begin());
      for (std::size_t i : groups[g]) ab[i] = b[i];
      out.fAB[g][j] = f(ab);
    }
  }
  return out;
}

// Ishigami function, a = 7, b = 0.1, inputs uniform on [-pi, pi].
constexpr double kIa = 7.0, kIb = 0.1;
double ishigami(std::span<const double> u) {
  const double pi = std::numbers::pi;
  const double x1 = -pi + 2 * pi * u[0], x2 = -pi + 2 * pi * u[1], x3 = -pi + 2 * pi * u[2];
  return std::sin(x1) + kIa * std::sin(x2) * std::sin(x2) + kIb * std::pow(x3, 4) * std::sin(x1);
}

struct Analytic {
  double s[3], st[3];
};
// V = a^2/8 + b pi^4/5 + b^2 pi^8/18 + 1/2, V1 = (1 + b pi^4/5)^2 / 2, V2 = a^2/8, V3 = 0,
// V13 = 8 b^2 pi^8 / 225 (the only interaction), so ST1 = (V1 + V13)/V, ST2 = S2, ST3 = V13/V.
Analytic ishigami_indices() {
  const double pi4 = std::pow(std::numbers::pi, 4), pi8 = pi4 * pi4;
  const double v = kIa * kIa / 8 + kIb * pi4 / 5 + kIb * kIb * pi8 / 18 + 0.5;
  const double v1 = 0.5 * std::pow(1 + kIb * pi4 / 5, 2), v2 = kIa * kIa / 8, v13 = 8 * kIb * kIb * pi8 / 225;
  return {{v1 / v, v2 / v, 0.0}, {(v1 + v13) / v, v2 / v, v13 / v}};
}

bool covers(const Estimate& e, double x) { return e.lo && e.hi && *e.lo <= x && x <= *e.hi; }

TEST(Sensitivity, IshigamiAnalyticValues) {
  // The textbook figures the estimates are checked against.
  const Analytic t = ishigami_indices();
  EXPECT_NEAR(t.s[0], 0.3139, 1e-4);
  EXPECT_NEAR(t.s[1], 0.4424, 1e-4);
  EXPECT_NEAR(t.st[0], 0.5576, 1e-4);
  EXPECT_NEAR(t.st[1], 0.4424, 1e-4);
  EXPECT_NEAR(t.st[2], 0.2437, 1e-4);
}

TEST(Sensitivity, Ishigami) {
  const Analytic t = ishigami_indices();
  const RadialValues v = evaluate(ishigami, 3, {{0}, {1}, {2}}, 1u << 14, 2024);
  const SobolResult r = v.indices(7);
  ASSERT_EQ(r.groups.size(), 3u);
  EXPECT_TRUE(r.note.empty()) << r.note;
  EXPECT_EQ(r.n, 1u << 14);
  const double pi4 = std::pow(std::numbers::pi, 4);
  EXPECT_NEAR(r.variance, kIa * kIa / 8 + kIb * pi4 / 5 + kIb * kIb * pi4 * pi4 / 18 + 0.5, 0.3);
  for (std::size_t g = 0; g < 3; ++g) {
    const auto& e = r.groups[g];
    SCOPED_TRACE("group " + std::to_string(g));
    EXPECT_EQ(e.rows_used, 1u << 14);
    ASSERT_TRUE(e.first.lo && e.first.hi && e.total.lo && e.total.hi);
    // Near the analytic value, in absolute terms and in standard errors, and inside the CI.
    EXPECT_NEAR(e.first.value, t.s[g], 0.03);
    EXPECT_NEAR(e.total.value, t.st[g], 0.03);
    EXPECT_LT(std::abs(e.first.value - t.s[g]), 3.5 * e.first_se);
    EXPECT_LT(std::abs(e.total.value - t.st[g]), 3.5 * e.total_se);
    EXPECT_TRUE(covers(e.first, t.s[g])) << *e.first.lo << " " << *e.first.hi;
    EXPECT_TRUE(covers(e.total, t.st[g])) << *e.total.lo << " " << *e.total.hi;
    // Interval brackets the estimate, standard error matches its width (~ 2 x 1.96 se).
    EXPECT_LE(*e.first.lo, e.first.value);
    EXPECT_GE(*e.first.hi, e.first.value);
    EXPECT_NEAR(*e.first.hi - *e.first.lo, 3.92 * e.first_se, 0.2 * 3.92 * e.first_se);
    EXPECT_NEAR(*e.total.hi - *e.total.lo, 3.92 * e.total_se, 0.2 * 3.92 * e.total_se);
    EXPECT_GT(e.first_se, 0.0);
    EXPECT_LT(e.first_se, 0.02);
    EXPECT_LT(e.total_se, 0.02);
  }
  const double sum = t.s[0] + t.s[1] + t.s[2];
  for (std::size_t g = 0; g < 3; ++g) {
    const auto& e = r.groups[g];
    std::printf("S%zu = %.4f [%.4f, %.4f] se %.4f (exact %.4f)   "
                "ST%zu = %.4f [%.4f, %.4f] se %.4f (exact %.4f)\n",
                g + 1, e.first.value, *e.first.lo, *e.first.hi, e.first_se, t.s[g], g + 1, e.total.value,
                *e.total.lo, *e.total.hi, e.total_se, t.st[g]);
  }
  std::printf("sum S = %.4f [%.4f, %.4f] (exact %.4f), V = %.4f\n", r.first_sum.value, *r.first_sum.lo,
              *r.first_sum.hi, sum, r.variance);
  EXPECT_NEAR(r.first_sum.value, sum, 0.04);
  EXPECT_TRUE(covers(r.first_sum, sum));
}

// The intervals are honest: over 20 independent replicas (design seeds and bootstrap seeds)
// each index's 95% interval covers the analytic value at least 17 times, and the bootstrap
// standard error matches the spread of the estimates across replicas.
TEST(Sensitivity, IshigamiCoverage) {
  const Analytic t = ishigami_indices();
  constexpr int kReps = 20;
  int cover_first[3] = {}, cover_total[3] = {}, cover_sum = 0;
  std::vector<double> est_first[3], est_total[3];
  double se_first[3] = {}, se_total[3] = {};
  for (int rep = 0; rep < kReps; ++rep) {
    const RadialValues v =
        evaluate(ishigami, 3, {{0}, {1}, {2}}, 2048, 100 + static_cast<std::uint64_t>(rep));
    const SobolResult r = v.indices(500 + static_cast<std::uint64_t>(rep), 500);
    for (std::size_t g = 0; g < 3; ++g) {
      cover_first[g] += covers(r.groups[g].first, t.s[g]) ? 1 : 0;
      cover_total[g] += covers(r.groups[g].total, t.st[g]) ? 1 : 0;
      est_first[g].push_back(r.groups[g].first.value);
      est_total[g].push_back(r.groups[g].total.value);
      se_first[g] += r.groups[g].first_se / kReps;
      se_total[g] += r.groups[g].total_se / kReps;
    }
    cover_sum += covers(r.first_sum, t.s[0] + t.s[1] + t.s[2]) ? 1 : 0;
  }
  auto sd = [](const std::vector<double>& x) {
    double m = 0, s = 0;
    for (double v : x) m += v / static_cast<double>(x.size());
    for (double v : x) s += (v - m) * (v - m);
    return std::sqrt(s / static_cast<double>(x.size() - 1));
  };
  for (std::size_t g = 0; g < 3; ++g) {
    SCOPED_TRACE("group " + std::to_string(g));
    EXPECT_GE(cover_first[g], 17);
    EXPECT_GE(cover_total[g], 17);
    // With 20 replicas the sample sd is within ~ +-35% of the truth at 95%.
    EXPECT_NEAR(sd(est_first[g]) / se_first[g], 1.0, 0.45);
    EXPECT_NEAR(sd(est_total[g]) / se_total[g], 1.0, 0.45);
    std::printf("group %zu: S covered %d/20, ST covered %d/20; sd/se S %.2f ST %.2f\n", g, cover_first[g],
                cover_total[g], sd(est_first[g]) / se_first[g], sd(est_total[g]) / se_total[g]);
  }
  EXPECT_GE(cover_sum, 17);
  std::printf("sum S covered %d/20\n", cover_sum);
}

// y = offset + sum_i c_i s_i u_i, u_i ~ U(0, 1): S_g = ST_g = sum_{i in g} c_i^2 s_i^2 / sum_i c_i^2 s_i^2.
// c s = (1, 1, 3, 1, 0), groups {0}, {1}, {2, 3}, {4}: indices 1/12, 1/12, 10/12, 0.
Model linear(double offset, double scale) {
  return [offset, scale](std::span<const double> u) {
    const double cs[5] = {1.0, -1.0, 3.0, 1.0, 0.0};
    double y = 0.0;
    for (std::size_t i = 0; i < 5; ++i) y += cs[i] * u[i];
    return offset + scale * y;
  };
}
const std::vector<std::vector<std::size_t>> kLinearGroups = {{0}, {1}, {2, 3}, {4}};

TEST(Sensitivity, LinearModelWithGroupAndInertInput) {
  const RadialValues v = evaluate(linear(0.0, 1.0), 5, kLinearGroups, 8192, 11);
  const SobolResult r = v.indices(3, 500);
  EXPECT_TRUE(r.note.empty()) << r.note;
  const double expected[4] = {1.0 / 12, 1.0 / 12, 10.0 / 12, 0.0};
  for (std::size_t g = 0; g < 3; ++g) {
    SCOPED_TRACE("group " + std::to_string(g));
    const auto& e = r.groups[g];
    EXPECT_NEAR(e.first.value, expected[g], 0.03);
    EXPECT_NEAR(e.total.value, expected[g], 0.03);
    EXPECT_TRUE(covers(e.first, expected[g]));
    EXPECT_TRUE(covers(e.total, expected[g]));
    EXPECT_LT(e.first_se, 0.02);
    EXPECT_LT(e.total_se, 0.02);
  }
  // The inert input: f(AB) == f(A) exactly, so both indices and their intervals are 0.
  const auto& z = r.groups[3];
  EXPECT_EQ(z.first.value, 0.0);
  EXPECT_EQ(z.total.value, 0.0);
  EXPECT_EQ(*z.first.lo, 0.0);
  EXPECT_EQ(*z.first.hi, 0.0);
  EXPECT_EQ(*z.total.hi, 0.0);
  EXPECT_EQ(z.total_se, 0.0);
  // Additive model: first-order effects explain everything.
  EXPECT_NEAR(r.first_sum.value, 1.0, 0.03);
  EXPECT_TRUE(covers(r.first_sum, 1.0));

  // A large offset and a small scale (a dimension around its nominal value) change nothing:
  // the values are centred before the products are formed.
  const RadialValues w = evaluate(linear(1e6, 1e-3), 5, kLinearGroups, 8192, 11);
  const SobolResult q = w.indices(3, 500);
  EXPECT_TRUE(q.note.empty()) << q.note;
  for (std::size_t g = 0; g < 4; ++g) {
    EXPECT_NEAR(q.groups[g].first.value, r.groups[g].first.value, 1e-5);
    EXPECT_NEAR(q.groups[g].total.value, r.groups[g].total.value, 1e-5);
    EXPECT_NEAR(*q.groups[g].first.lo, *r.groups[g].first.lo, 1e-5);
    EXPECT_NEAR(*q.groups[g].total.hi, *r.groups[g].total.hi, 1e-5);
  }
}

// Direct evaluation of the header's equations, row by row (the reference for the NaN test).
struct Reference {
  double variance;
  std::vector<double> first, total;
};
Reference reference(const RadialValues& v) {
  const std::size_t n = v.fA.size();
  auto ok = [](double x) { return std::isfinite(x); };
  double m = 0.0, nb = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    if (ok(v.fA[j]) && ok(v.fB[j])) {
      m += v.fA[j] + v.fB[j];
      nb += 1;
    }
  }
  m /= 2 * nb;
  double var = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    if (ok(v.fA[j]) && ok(v.fB[j])) var += (v.fA[j] - m) * (v.fA[j] - m) + (v.fB[j] - m) * (v.fB[j] - m);
  }
  var /= 2 * nb - 1;
  Reference r{var, {}, {}};
  for (const auto& ab : v.fAB) {
    double vg = 0.0, vt = 0.0, ng = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
      if (!(ok(v.fA[j]) && ok(v.fB[j]) && ok(ab[j]))) continue;
      vg += (v.fB[j] - m) * (ab[j] - v.fA[j]);
      vt += (v.fA[j] - ab[j]) * (v.fA[j] - ab[j]);
      ng += 1;
    }
    r.first.push_back(vg / ng / var);
    r.total.push_back(vt / (2 * ng) / var);
  }
  return r;
}

TEST(Sensitivity, FailedEvaluationsDropTheirRows) {
  RadialValues v = evaluate(linear(5.0, 1.0), 5, kLinearGroups, 1000, 5);
  v.fA[3] = kNaN;                                       // row 3 out of everything
  v.fB[7] = std::numeric_limits<double>::infinity();   // row 7 too
  v.fAB[1][3] = kNaN;                                   // already out
  v.fAB[1][5] = kNaN;                                   // row 5 out of group 1 only
  v.fAB[2][9] = kNaN;                                   // row 9 out of group 2 only
  v.fAB[2][10] = kNaN;
  const SobolResult r = v.indices(9, 200);
  EXPECT_TRUE(r.note.empty()) << r.note;
  EXPECT_EQ(r.n, 998u);
  EXPECT_EQ(r.groups[0].rows_used, 998u);
  EXPECT_EQ(r.groups[1].rows_used, 997u);
  EXPECT_EQ(r.groups[2].rows_used, 996u);
  EXPECT_EQ(r.groups[3].rows_used, 998u);
  const Reference ref = reference(v);
  EXPECT_NEAR(r.variance, ref.variance, 1e-12);
  for (std::size_t g = 0; g < 4; ++g) {
    SCOPED_TRACE("group " + std::to_string(g));
    EXPECT_TRUE(std::isfinite(r.groups[g].first.value));
    EXPECT_NEAR(r.groups[g].first.value, ref.first[g], 1e-12);
    EXPECT_NEAR(r.groups[g].total.value, ref.total[g], 1e-12);
    EXPECT_TRUE(r.groups[g].first.lo && r.groups[g].total.hi);
  }
  // Rows 3 and 7 removed outright give the same estimates for the groups that keep the rest.
  RadialValues cut = v;
  for (auto* x : {&cut.fA, &cut.fB, &cut.fAB[0], &cut.fAB[1], &cut.fAB[2], &cut.fAB[3]}) {
    x->erase(x->begin() + 7);
    x->erase(x->begin() + 3);
  }
  const SobolResult c = cut.indices(9, 0);
  EXPECT_EQ(c.n, 998u);
  EXPECT_NEAR(c.variance, r.variance, 1e-12);
  EXPECT_NEAR(c.groups[0].first.value, r.groups[0].first.value, 1e-12);
  EXPECT_NEAR(c.groups[3].total.value, r.groups[3].total.value, 1e-12);
  EXPECT_FALSE(c.groups[0].first.lo.has_value());  // no bootstrap asked
  EXPECT_EQ(c.groups[0].first_se, 0.0);

  // A group whose every f(AB) failed: its indices are NaN with a reason, the others stand.
  RadialValues dead = v;
  std::fill(dead.fAB[1].begin(), dead.fAB[1].end(), kNaN);
  const SobolResult d = dead.indices(9, 100);
  EXPECT_EQ(d.groups[1].rows_used, 0u);
  EXPECT_TRUE(std::isnan(d.groups[1].first.value));
  EXPECT_TRUE(std::isnan(d.groups[1].total.value));
  EXPECT_FALSE(d.groups[1].first.lo.has_value());
  EXPECT_TRUE(std::isnan(d.first_sum.value));
  EXPECT_NE(d.note.find("group 1"), std::string::npos) << d.note;
  EXPECT_NEAR(d.groups[0].first.value, r.groups[0].first.value, 1e-12);

  // Every row failed: nothing defined, no exception.
  RadialValues none = v;
  std::fill(none.fB.begin(), none.fB.end(), kNaN);
  const SobolResult e = none.indices(9, 100);
  EXPECT_EQ(e.n, 0u);
  EXPECT_FALSE(e.note.empty());
  EXPECT_TRUE(std::isnan(e.groups[0].first.value));
}

TEST(Sensitivity, ConstantOutputIsFlagged) {
  for (double jitter : {0.0, 1e-15}) {
    RadialValues v = evaluate([](std::span<const double>) { return 5.0; }, 2, {{0}, {1}}, 500, 1);
    // Rounding-level noise (about 1 ulp of 5) still counts as constant.
    for (std::size_t j = 0; j < v.fA.size(); ++j) v.fA[j] += jitter * static_cast<double>(j % 7);
    const SobolResult r = v.indices(1, 100);
    EXPECT_NE(r.note.find("constant"), std::string::npos) << r.note;
    EXPECT_LT(r.variance, 1e-25);
    for (const auto& g : r.groups) {
      EXPECT_TRUE(std::isnan(g.first.value));
      EXPECT_TRUE(std::isnan(g.total.value));
      EXPECT_FALSE(g.first.lo.has_value());
    }
    EXPECT_TRUE(std::isnan(r.first_sum.value));
  }
}

TEST(Sensitivity, DeterministicFromTheSeed) {
  const RadialValues v = evaluate(ishigami, 3, {{0}, {1}, {2}}, 2048, 3);
  const SobolResult a = v.indices(42, 300), b = v.indices(42, 300), c = v.indices(43, 300);
  for (std::size_t g = 0; g < 3; ++g) {
    EXPECT_EQ(a.groups[g].first.value, b.groups[g].first.value);
    EXPECT_EQ(*a.groups[g].first.lo, *b.groups[g].first.lo);
    EXPECT_EQ(*a.groups[g].total.hi, *b.groups[g].total.hi);
    EXPECT_EQ(a.groups[g].total_se, b.groups[g].total_se);
    // Another bootstrap seed: same estimates, other intervals.
    EXPECT_EQ(a.groups[g].first.value, c.groups[g].first.value);
    EXPECT_NE(*a.groups[g].first.lo, *c.groups[g].first.lo);
  }
  EXPECT_EQ(*a.first_sum.lo, *b.first_sum.lo);
}

TEST(Sensitivity, RejectsMismatchedSizes) {
  const std::vector<double> a(10, 1.0), b(9, 1.0), ab(10, 1.0);
  EXPECT_THROW(ps::sobol_indices(a, b, {std::span<const double>(ab)}, 1), poise::Error);
  EXPECT_THROW(ps::sobol_indices(a, a, {std::span<const double>(b)}, 1), poise::Error);
  EXPECT_THROW(ps::sobol_indices(a, a, {}, 1), poise::Error);
}

}  // namespace
