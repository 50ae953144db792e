// The influence-coefficient method (estimators/influence_coefficients.h) on campaigns whose
// truth is known: exact recovery without noise, standard errors that cover at their stated
// level with noise, the correction that cancels the rotor's own readings, and refusals.
#include "estimators/influence_coefficients.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"
#include "balancing_test_rotor.h"

namespace poise::estimators {
namespace {

using P = Phasor;

// The shared rotor: two planes, three sensors (balancing_test_rotor.h).
using test_rotor::kA;
using test_rotor::kH;

BalancingRun simulated_run(const std::vector<P>& w, std::mt19937_64* g, double noise) {
  std::normal_distribution<double> n(0.0, noise);
  BalancingRun r;
  r.name = "run";
  r.masses = w;
  for (std::size_t s = 0; s < kA.size(); ++s) {
    P v = kA[s];
    for (std::size_t p = 0; p < w.size(); ++p) v += kH[s][p] * w[p];
    if (g) v += P(n(*g), n(*g));
    r.readings.push_back(v);
  }
  return r;
}

// The campaign: as found, a trial in each plane, both, and `extra` runs with other masses.
std::vector<BalancingRun> campaign(std::mt19937_64* g, double noise, int extra) {
  std::vector<std::vector<P>> masses = {{0.0, 0.0}, {std::polar(10.0, 0.6), 0.0}, {0.0, std::polar(8.0, 2.2)}};
  for (int k = 0; k < extra; ++k) masses.push_back({std::polar(10.0, 0.6 + k), std::polar(8.0, 2.2 - 0.7 * k)});
  std::vector<BalancingRun> runs;
  for (const auto& w : masses) runs.push_back(simulated_run(w, g, noise));
  return runs;
}

TEST(InfluenceCoefficients, ExactReadingsGiveTheCoefficientsAndACorrectionThatCancels) {
  const InfluenceCalibration c = calibrate(campaign(nullptr, 0.0, 0), 2);
  EXPECT_EQ(c.dof, 0u);
  for (std::size_t s = 0; s < 3; ++s) {
    EXPECT_NEAR(std::abs(c.initial[s].value - kA[s]), 0.0, 1e-12);
    EXPECT_FALSE(c.initial[s].se.has_value());
    for (std::size_t p = 0; p < 2; ++p) EXPECT_NEAR(std::abs(c.h[s][p].value - kH[s][p]), 0.0, 1e-12);
  }
  // Three sensors, two planes: the least-squares correction leaves the part of a that H cannot
  // reach; its residual is orthogonal to H's columns (the normal equations).
  const Correction corr = correction(c);
  for (std::size_t p = 0; p < 2; ++p) {
    P dot = 0.0;
    for (std::size_t s = 0; s < 3; ++s) dot += std::conj(kH[s][p]) * corr.residual[s];
    EXPECT_NEAR(std::abs(dot), 0.0, 1e-12);
  }
  // A run of unknown masses: its masses are found again.
  const std::vector<P> w = {std::polar(3.0, 1.1), std::polar(5.0, -0.4)};
  const std::vector<P> found = unbalance_of(c, simulated_run(w, nullptr, 0.0).readings);
  for (std::size_t p = 0; p < 2; ++p) EXPECT_NEAR(std::abs(found[p] - w[p]), 0.0, 1e-10);
}

// Noise of sd 0.02 on each part of each reading, 6 runs (3 complex degrees of freedom, 6 real
// ones: each part's t has 2 (R - P - 1)): over 2000 campaigns each coefficient's part lies within
// t(0.975, 6) standard errors of the truth in about 95% of them (allowed 93-97%).
TEST(InfluenceCoefficients, StandardErrorsCoverAtTheirLevel) {
  std::mt19937_64 g(12);
  const double t975_6 = 2.4469118511449692;
  int covered = 0, total = 0;
  for (int run = 0; run < 2000; ++run) {
    const InfluenceCalibration c = calibrate(campaign(&g, 0.02, 3), 2);
    ASSERT_EQ(c.dof, 3u);
    for (std::size_t s = 0; s < 3; ++s) {
      const P e = c.h[s][0].value - kH[s][0];
      covered += std::abs(e.real()) <= t975_6 * *c.h[s][0].se ? 1 : 0;
      ++total;
    }
  }
  const double share = static_cast<double>(covered) / total;
  EXPECT_GT(share, 0.93);
  EXPECT_LT(share, 0.97);
}

TEST(InfluenceCoefficients, TooFewRunsOrPlanesLoadedAlikeAreRefused) {
  std::vector<BalancingRun> runs = campaign(nullptr, 0.0, 0);
  runs.pop_back();
  EXPECT_THROW(calibrate(runs, 2), Error);
  std::vector<BalancingRun> alike = campaign(nullptr, 0.0, 0);
  alike[1].masses = std::vector<P>{std::polar(4.0, 0.1), std::polar(4.0, 0.1)};
  alike[2].masses = std::vector<P>{std::polar(6.0, 0.1), std::polar(6.0, 0.1)};
  EXPECT_THROW(calibrate(alike, 2), Error);
}

}  // namespace
}  // namespace poise::estimators
