// Chance constraints with confidence, the fresh-sample verdicts, failure shares and the
// equivalence of choices: each checked on a problem whose answer is known.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <boost/math/distributions/binomial.hpp>

#include "core/error.h"
#include "optimize/choice_decision.h"
#include "engine/results/confidence_bound.h"
#include "optimize/design_search.h"
#include "optimize/fresh_check.h"
#include "optimize/optimizer.h"
#include "sampling/statistics.h"

namespace poise::optimize {
namespace {

std::vector<double> normals(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 g(seed);
  std::normal_distribution<double> d;
  std::vector<double> v(n);
  for (auto& x : v) x = d(g);
  return v;
}

TEST(ConfidenceBound, OrderStatisticBoundIsTheBinomialRank) {
  // Values 1..n: the upper 95% bound of p90 is X_(k), k - 1 the smallest x with
  // P(Binomial(n, 0.9) <= x) >= 0.95, recomputed here by summing the pmf.
  const std::size_t n = 200;
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<double>(n - i);  // any order
  double cdf = 0.0;
  std::size_t x = 0;
  for (;; ++x) {
    cdf += boost::math::pdf(boost::math::binomial_distribution<double>(n, 0.9), static_cast<double>(x));
    if (cdf >= 0.95) break;
  }
  const auto up = one_sided_bound({v, {}}, "p90", parse_bound("upper95"));
  ASSERT_TRUE(up.has_value());
  EXPECT_DOUBLE_EQ(*up, static_cast<double>(x + 1));  // X_(x+1) = x + 1 for values 1..n
  const auto lo = one_sided_bound({v, {}}, "p90", parse_bound("lower95"));
  ASSERT_TRUE(lo.has_value());
  EXPECT_LT(*lo, engine::statistic(v, "p90"));
  EXPECT_GT(*up, engine::statistic(v, "p90"));
  // Too few samples for an upper bound of p99.73.
  EXPECT_FALSE(one_sided_bound({std::vector<double>(v.begin(), v.begin() + 50), {}}, "p99.73", parse_bound("upper95")));
}

TEST(ConfidenceBound, UpperBoundOfAQuantileCoversAtItsConfidence) {
  // Standard normal, p95 = 1.6449: the upper 95% bound lies above it in >= 95% of the draws.
  const double q95 = 1.6448536269514722;
  int covered = 0, point_above = 0;
  const int trials = 400;
  for (int t = 0; t < trials; ++t) {
    const auto v = normals(100, 1000 + t);
    covered += *one_sided_bound({v, {}}, "p95", parse_bound("upper95")) >= q95 ? 1 : 0;
    point_above += engine::statistic(v, "p95") >= q95 ? 1 : 0;
  }
  EXPECT_GE(covered, 0.93 * trials);  // binomial noise of 400 trials around >= 0.95
  EXPECT_LT(point_above, 0.65 * trials);  // the point value alone: about half
  EXPECT_GT(point_above, 0.35 * trials);
}

TEST(ConfidenceBound, ClopperPearsonAndStudentClosedForms) {
  // No unit of 10 meets the requirement: upper one-sided 95% bound 1 - 0.05^(1/10).
  std::vector<double> v(10, 2.0);
  EXPECT_NEAR(*one_sided_bound({v, {}}, "fraction_le:1", parse_bound("upper95")), 1.0 - std::pow(0.05, 0.1), 1e-12);
  // All 10 meet it: lower bound 0.05^(1/10).
  EXPECT_NEAR(*one_sided_bound({v, {}}, "fraction_le:3", parse_bound("lower95")), std::pow(0.05, 0.1), 1e-12);
  // Mean of {1, 2, 3, 4}: 2.5 + t(0.95, 3) s / 2 with s = 1.29099, t = 2.353363.
  EXPECT_NEAR(*one_sided_bound({{1, 2, 3, 4}, {}}, "mean", parse_bound("upper95")),
              2.5 + 2.3533634348018264 * std::sqrt(5.0 / 3.0) / 2.0, 1e-9);
  EXPECT_FALSE(one_sided_bound({v, {}}, "max", parse_bound("upper95")));
  EXPECT_TRUE(bound_supported("p99.73"));
  EXPECT_TRUE(bound_supported("fraction_ge:0.5"));
  EXPECT_FALSE(bound_supported("max"));
  EXPECT_THROW(parse_bound("upper"), Error);
  EXPECT_THROW(parse_bound("upper40"), Error);
  EXPECT_THROW(parse_bound("middle95"), Error);
  EXPECT_EQ(to_string(parse_bound("lower97.5")), "lower97.5");
}

TEST(ConfidenceBound, ReplicateBoundAgreesWithSummarizeReplicates) {
  // 8 replicates of 64: the one-sided 97.5% bounds are the ends of the two-sided 95%
  // interval sampling::summarize_replicates computes on its own.
  const auto v = normals(512, 77);
  std::vector<std::size_t> rep(v.size()), ok(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    rep[i] = i / 64;
    ok[i] = i;
  }
  const SampleSet s = sample_set(v, ok, 64);
  EXPECT_EQ(s.replicates(), 8u);
  const sampling::Summary ref = sampling::summarize_replicates(v, rep);
  EXPECT_NEAR(*one_sided_bound(s, "p95", parse_bound("upper97.5")), *ref.p95.hi, 1e-12);
  EXPECT_NEAR(*one_sided_bound(s, "p95", parse_bound("lower97.5")), *ref.p95.lo, 1e-12);
  const Interval i = interval(s, "mean");
  EXPECT_NEAR(*i.hi, *ref.mean.hi, 1e-12);
  EXPECT_EQ(i.method, "8 replicates");
}

// A problem with a known optimum under noise: the largest gain x whose output x z (z standard
// normal) keeps p95 <= 1, i.e. x* = 1 / 1.6449 = 0.6080. The search sees 64 draws (common
// random numbers); on the point value it lands at 1 / p95(sample), which exceeds x* (so
// the true p95 exceeds 1) in about half of the draws; on the upper 95% bound it exceeds x*
// in at most about 5%.
TEST(ChanceConstraint, PointValueIsFooledByTheDrawTheConfidenceBoundIsNot) {
  const double x_star = 1.0 / 1.6448536269514722;
  int fooled_point = 0, fooled_bound = 0;
  const int draws = 60;
  for (int d = 0; d < draws; ++d) {
    const auto z = normals(64, 5000 + d);
    auto solve = [&](const BoundSpec& bound) {
      const Problem f = [&](const std::vector<double>& x) {
        std::vector<double> y(z.size());
        for (std::size_t i = 0; i < z.size(); ++i) y[i] = x[0] * z[i];
        Evaluation e;
        e.objective = -x[0];
        e.constraints = {*one_sided_bound({y, {}}, "p95", bound) - 1.0};
        return e;
      };
      Options o;
      o.constraints = 1;
      o.max_evaluations = 80;
      o.xtol_rel = 1e-6;
      const Result r = minimize(f, {{"gain", 0.05, 2.0, 0.3}}, o);
      EXPECT_TRUE(r.feasible);
      return r.x[0];
    };
    const double xp = solve(BoundSpec{}), xb = solve(parse_bound("upper95"));
    // The point-value optimum is 1 / p95 of the draw (exact up to the search's tolerance).
    EXPECT_NEAR(xp, 1.0 / engine::statistic(z, "p95"), 1e-3);
    EXPECT_LT(xb, xp);
    fooled_point += xp > x_star ? 1 : 0;
    fooled_bound += xb > x_star ? 1 : 0;
  }
  std::printf("known optimum 0.608: point value beyond it in %d of %d draws, upper 95%% bound in %d\n", fooled_point,
              draws, fooled_bound);
  EXPECT_GT(fooled_point, draws / 4);
  EXPECT_LE(fooled_bound, draws / 10);
}

engine::McResult evaluation(std::size_t samples, std::size_t failures, double scale) {
  engine::McResult e;
  e.names = {"err_mm"};
  e.n = samples;
  e.failures = failures;
  e.failed = {{samples - 1, "CVODE failed"}};
  const auto z = normals(samples - failures, 9);
  for (std::size_t i = 0; i < z.size(); ++i) {
    e.values.resize(1);
    e.values[0].push_back(scale * std::fabs(z[i]));
    e.ok_index.push_back(i);
  }
  return e;
}

OptimizationSpec spec_with(double at_most, const std::string& bound = "value") {
  OptimizationSpec s;
  s.base.max_failure_share = 0.05;
  s.objective_output = "err_mm";
  s.objective_statistic = "p95";
  s.variables = {{"x", "mm", 0, 1, 0.5}};
  Requirement r;
  r.name = "err_mm.p95";
  r.output = "err_mm";
  r.statistic = "p95";
  r.at_most = at_most;
  r.bound = parse_bound(bound);
  s.constraints = {r};
  return s;
}

TEST(FailureShare, AnEvaluationOverTheShareFailsWithItsReason) {
  const OptimizationSpec spec = spec_with(10.0);
  const ScoredDesign ok = score_design(spec, {0.5}, evaluation(400, 12, 1.0));  // 3%
  EXPECT_TRUE(ok.primary.ok);
  EXPECT_DOUBLE_EQ(ok.failure_share, 0.03);
  const ScoredDesign bad = score_design(spec, {0.5}, evaluation(400, 40, 1.0));  // 10%
  EXPECT_FALSE(bad.primary.ok);
  EXPECT_DOUBLE_EQ(bad.failure_share, 0.1);
  EXPECT_NE(bad.primary.message.find("40 of 400 samples failed (10.0%, over the study's max_failure_share 0.05)"),
            std::string::npos) << bad.primary.message;
  EXPECT_NE(bad.primary.message.find("CVODE failed"), std::string::npos);
  // The fresh check fails on failures alone, whatever the statistics.
  const FreshCheck f = check_design(spec, {0.5}, evaluation(400, 40, 1.0), 3);
  EXPECT_EQ(f.verdict, Verdict::kFails);
  EXPECT_FALSE(f.failures_ok);
  EXPECT_NE(f.problems().find("40 of 400 samples failed"), std::string::npos) << f.problems();
  EXPECT_EQ(check_design(spec, {0.5}, evaluation(400, 12, 1.0), 3).verdict, Verdict::kPasses);
}

TEST(FreshCheck, PassesStraddlesOrFails) {
  // |z| of 4000 normals: p95 = 1.96 with a 95% interval of about +-0.08.
  const auto e = evaluation(4000, 0, 1.0);
  const double p95 = engine::statistic(e.values[0], "p95");
  EXPECT_EQ(check_design(spec_with(p95 + 0.3), {0.5}, e, 1).verdict, Verdict::kPasses);
  EXPECT_EQ(check_design(spec_with(p95 + 0.01), {0.5}, e, 1).verdict, Verdict::kStraddles);
  EXPECT_EQ(check_design(spec_with(p95 - 0.01), {0.5}, e, 1).verdict, Verdict::kFails);
  // Stated on the upper 95% bound: judged on that bound.
  const FreshCheck b = check_design(spec_with(p95 + 0.01, "upper95"), {0.5}, e, 1);
  EXPECT_EQ(b.verdict, Verdict::kStraddles);
  ASSERT_TRUE(b.constraints[0].bound.has_value());
  EXPECT_NE(b.describe_constraint(0).find("upper 95% bound"), std::string::npos) << b.describe_constraint(0);
}

TEST(Equivalence, VerdictOnAKnownDifference) {
  // Paired: a = 1.10 b on the same units, so p95(a) - p95(b) = 0.10 p95(b) exactly.
  const auto z = normals(2000, 4);
  std::vector<double> b, a10, a1;
  std::vector<std::size_t> units;
  for (std::size_t i = 0; i < z.size(); ++i) {
    b.push_back(1.0 + std::fabs(z[i]));
    a10.push_back(1.10 * b.back());
    a1.push_back(1.01 * b.back());
    units.push_back(i);
  }
  const double pb = engine::statistic(b, "p95");
  const Difference d10 = difference(a10, units, b, units, "p95", 1);
  EXPECT_TRUE(d10.paired);
  EXPECT_NEAR(d10.value, 0.10 * pb, 1e-12);
  ASSERT_TRUE(d10.lo && d10.hi);
  EXPECT_LE(*d10.lo, d10.value);
  EXPECT_GE(*d10.hi, d10.value);
  const Equivalence e10 = equivalence(d10, 0.05 * pb);
  EXPECT_FALSE(e10.shown);
  EXPECT_TRUE(e10.worse);  // 10% worse: beyond a 5% margin
  const Equivalence e1 = equivalence(difference(a1, units, b, units, "p95", 1), 0.05 * pb);
  EXPECT_TRUE(e1.shown);  // 1% worse: within 5%
  // Unpaired and few units: a wide interval, equivalence not shown on the upper side.
  std::vector<double> small_a(a1.begin(), a1.begin() + 40), small_b(b.begin() + 1000, b.begin() + 1040);
  std::vector<std::size_t> ua(40), ub(40);
  for (std::size_t i = 0; i < 40; ++i) {
    ua[i] = i;
    ub[i] = 1000 + i;
  }
  const Difference du = difference(small_a, ua, small_b, ub, "p95", 1);
  EXPECT_FALSE(du.paired);
  const Equivalence eu = equivalence(du, 0.05 * pb);
  EXPECT_FALSE(eu.shown);
  const std::string text = equivalence_clause(du, eu, "mN*m", "5%");
  EXPECT_NE(text.find("so equivalence is NOT shown"), std::string::npos) << text;
  EXPECT_NE(text.find("exceeds the 5% margin"), std::string::npos) << text;
  EXPECT_NE(equivalence_clause(d10, e10, "mN*m", "5%").find("worse beyond the margin"), std::string::npos);
}

}  // namespace
}  // namespace poise::optimize
