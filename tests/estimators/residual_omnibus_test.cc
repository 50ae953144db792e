// Tests of estimators/residual_omnibus: the Kolmogorov tail at its tabulated 5 % point, the
// Ljung-Box statistic recomputed by hand, each test catching the structure it is made for
// (step -> CUSUM with its place, alternation -> runs, repeats that disagree -> lack of fit,
// too much scatter -> declared noise, a sawtooth in time -> periodogram with its period), the
// periodogram's statistic recomputed by a direct sum, and the family's level on white residuals.
#include "estimators/residual_omnibus.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <numeric>
#include <random>

namespace poise::estimators {
namespace {

OmnibusInput input(const std::vector<double>& r) {
  OmnibusInput in;
  in.residual = r;
  in.order.resize(r.size());
  std::iota(in.order.begin(), in.order.end(), std::size_t{0});
  for (std::size_t i = 0; i < r.size(); ++i) {
    in.theta_deg.push_back(10.0 * static_cast<double>(i % 36));
    in.time_s.push_back(60.0 * static_cast<double>(i));
    in.lines.push_back(i + 2);
  }
  return in;
}

std::vector<double> white(std::size_t n, std::uint64_t seed, double sd = 1.0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, sd);
  std::vector<double> e(n);
  for (double& v : e) v = g(rng);
  const double m = std::accumulate(e.begin(), e.end(), 0.0) / static_cast<double>(n);
  for (double& v : e) v -= m;  // a fitted constant leaves zero-mean residuals
  return e;
}

const StructureTest& test_named(const OmnibusResult& r, const std::string& name) {
  for (const auto& t : r.tests) {
    if (t.name == name) return t;
  }
  throw std::runtime_error("no test " + name);
}

TEST(ResidualOmnibus, KolmogorovTailAtItsTabulatedPoints) {
  EXPECT_NEAR(brownian_bridge_sup_tail(1.3581), 0.05, 2e-4);
  EXPECT_NEAR(brownian_bridge_sup_tail(1.6276), 0.01, 1e-4);
  EXPECT_EQ(brownian_bridge_sup_tail(0.1), 1.0);
}

TEST(ResidualOmnibus, LjungBoxIsRecomputedByHand) {
  const std::vector<double> r = white(40, 3);
  const OmnibusResult o = omnibus_check(input(r));
  const StructureTest& lb = test_named(o, "ljung_box");
  ASSERT_TRUE(lb.examined);
  double c0 = 0.0, q = 0.0;
  for (double v : r) c0 += v * v;  // mean is zero
  for (int k = 1; k <= 4; ++k) {  // h = round(ln 40) = 4
    double ck = 0.0;
    for (int i = k; i < 40; ++i) ck += r[i] * r[i - k];
    q += (ck / c0) * (ck / c0) / (40.0 - k);
  }
  EXPECT_NEAR(lb.statistic, 40.0 * 42.0 * q, 1e-9);
}

TEST(ResidualOmnibus, StepIsFoundByTheCusumWithItsPlace) {
  std::vector<double> r = white(36, 4, 0.2);
  for (std::size_t i = 0; i < 36; ++i) r[i] += i < 18 ? -0.5 : 0.5;
  const OmnibusResult o = omnibus_check(input(r));
  EXPECT_TRUE(o.unexplained);
  EXPECT_LT(test_named(o, "cusum_step").p_value, 1e-3);
  EXPECT_NE(o.where.find("level shift"), std::string::npos) << o.where;
  EXPECT_NE(o.message.find("Unexplained structure"), std::string::npos);
  EXPECT_NE(o.message.find("estimate carries it"), std::string::npos);
}

TEST(ResidualOmnibus, AlternationIsFoundByTheRunsTest) {
  std::vector<double> r = white(36, 5, 0.1);
  for (std::size_t i = 0; i < 36; ++i) r[i] += i % 2 ? 0.4 : -0.4;
  const OmnibusResult o = omnibus_check(input(r));
  EXPECT_TRUE(o.unexplained);
  EXPECT_GT(test_named(o, "runs").statistic, 3.0);  // too many runs
}

TEST(ResidualOmnibus, RepeatsThatDisagreeWithTheModelAreALackOfFit) {
  // 36 positions twice; the same 9-per-turn pattern both times plus small independent noise.
  std::vector<double> r = white(72, 6, 0.05);
  for (std::size_t i = 0; i < 72; ++i) r[i] += 0.5 * std::sin(9.0 * 10.0 * static_cast<double>(i % 36) * M_PI / 180.0 + 0.3);
  const OmnibusResult o = omnibus_check(input(r));
  const StructureTest& lof = test_named(o, "lack_of_fit");
  ASSERT_TRUE(lof.examined) << lof.note;
  EXPECT_LT(lof.p_value, 1e-6);
  EXPECT_TRUE(o.unexplained);
  EXPECT_FALSE(test_named(omnibus_check(input(white(36, 6))), "lack_of_fit").examined);
}

TEST(ResidualOmnibus, MoreScatterThanTheDeclaredNoiseIsFlagged) {
  OmnibusInput in = input(white(36, 7, 0.4));
  in.noise = 0.2;
  const OmnibusResult o = omnibus_check(in);
  EXPECT_LT(test_named(o, "declared_noise").p_value, 1e-4);
  EXPECT_TRUE(o.unexplained);
  in.noise = 0.4;
  EXPECT_GT(test_named(omnibus_check(in), "declared_noise").p_value, 1e-3);
}

TEST(ResidualOmnibus, SawtoothInTimeIsFoundByThePeriodogramWithItsPeriod) {
  // A sawtooth of period 10 points (600 s) over 36 points: no divisor of the record, so its
  // fundamental falls between two Fourier frequencies. Peak to peak 1.2, noise sd 0.2.
  std::vector<double> r = white(36, 9, 0.2);
  for (std::size_t i = 0; i < 36; ++i) r[i] += 1.2 * (std::fmod(static_cast<double>(i) / 10.0, 1.0) - 0.5);
  const OmnibusResult o = omnibus_check(input(r));
  const StructureTest& pg = test_named(o, "periodogram");
  ASSERT_TRUE(pg.examined) << pg.note;
  EXPECT_LT(pg.p_value, 0.01);
  EXPECT_TRUE(o.unexplained);
  const std::size_t at = o.where.find("period ");
  ASSERT_NE(at, std::string::npos) << o.where;
  double period_points = 0.0, period_s = 0.0;
  ASSERT_EQ(std::sscanf(o.where.c_str() + at, "period %lf points (about %lf s)", &period_points, &period_s), 2);
  EXPECT_NEAR(period_points, 10.0, 0.5) << o.where;
  EXPECT_NEAR(period_s, 600.0, 30.0) << o.where;  // 60 s per point
}

TEST(ResidualOmnibus, PeriodogramStatisticIsRecomputedByADirectSum) {
  const std::vector<double> r = white(30, 10);  // zero mean
  double energy = 0.0, best = 0.0;
  for (double v : r) energy += v * v;
  for (int j = 1; j <= 8 * 14; ++j) {  // f = j / 240 up to 14 / 30 cycles per point
    std::complex<double> s = 0.0;
    for (int t = 0; t < 30; ++t) s += r[t] * std::polar(1.0, -2.0 * M_PI * j * t / 240.0);
    best = std::max(best, std::norm(s));
  }
  EXPECT_NEAR(test_named(omnibus_check(input(r)), "periodogram").statistic, best / energy, 1e-9);
}

TEST(ResidualOmnibus, WhiteResidualsAreRarelyFlagged) {
  int flagged = 0;
  constexpr int kRuns = 400;
  for (int k = 0; k < kRuns; ++k) flagged += omnibus_check(input(white(36, 1000 + k))).unexplained;
  const double rate = static_cast<double>(flagged) / kRuns;
  std::printf("omnibus on white residuals: %d of %d flagged (%.3f)\n", flagged, kRuns, rate);
  EXPECT_LE(rate, 0.05 + 2.0 * std::sqrt(0.05 * 0.95 / kRuns));
  const OmnibusResult o = omnibus_check(input(white(36, 1)));
  EXPECT_FALSE(o.message.empty());  // never silent
}

}  // namespace
}  // namespace poise::estimators

namespace poise::estimators {
namespace {

TEST(ResidualOmnibus, PointsOwnStandardErrorsAreTheNoiseLevel) {
  // Residuals of sd 0.2 against standard errors of 0.1 (half the points) and 0.3.
  OmnibusInput in = input(white(36, 8, 0.2));
  for (std::size_t i = 0; i < 36; ++i) in.noise_per_point.push_back(i % 2 ? 0.3 : 0.1);
  const OmnibusResult o = omnibus_check(in);
  const StructureTest& t = test_named(o, "declared_noise");
  ASSERT_TRUE(t.examined);
  double chi2 = 0.0;
  for (std::size_t i = 0; i < 36; ++i) chi2 += std::pow(in.residual[i] / in.noise_per_point[i], 2);
  EXPECT_NEAR(t.statistic, chi2, 1e-9);
  EXPECT_LT(t.p_value, 1e-3);  // E[chi2] = 36 * 0.04 * (100 + 11.1) / 2 = 80 on 33 dof
}

}  // namespace
}  // namespace poise::estimators
