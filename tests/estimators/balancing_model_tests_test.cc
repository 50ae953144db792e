// The linear model's tests (estimators/balancing_model_tests.h) on campaigns of the linear model
// itself with one effect planted: each effect is found and named, clean campaigns find nothing
// in more than a few percent, and a campaign too small for a test says which runs it needs.
#include "estimators/balancing_model_tests.h"
#include "balancing_test_rotor.h"

#include <gtest/gtest.h>

#include <complex>
#include <random>

namespace poise::estimators {
namespace {

using P = Phasor;

// The shared rotor: two planes, three sensors (balancing_test_rotor.h).
using test_rotor::kA;
using test_rotor::kH;

enum class Planted { kNone, kMirror, kCubic };

// Eight runs: as found, a ladder in plane 0 (1x, 2x, 3x at one angle), trials at other angles.
// own: the rotor's own readings (kA where not given).
std::vector<BalancingRun> campaign(std::mt19937_64& g, Planted effect, double noise, double gain = 1.0,
                                   const std::vector<P>& own = kA) {
  const std::vector<std::vector<P>> masses = {{0.0, 0.0},
                                              {std::polar(10.0, 0.6), 0.0},
                                              {std::polar(20.0, 0.6), 0.0},
                                              {std::polar(30.0, 0.6), 0.0},
                                              {0.0, std::polar(8.0, 2.2)},
                                              {0.0, std::polar(16.0, -1.0)},
                                              {std::polar(12.0, 2.8), std::polar(8.0, 0.2)},
                                              {std::polar(9.0, -2.0), std::polar(12.0, 1.4)}};
  std::normal_distribution<double> n(0.0, noise);
  std::vector<BalancingRun> runs;
  for (std::size_t r = 0; r < masses.size(); ++r) {
    BalancingRun run;
    run.name = "run";
    run.declared = r;
    run.masses = masses[r];
    for (std::size_t s = 0; s < kA.size(); ++s) {
      P v = own[s];
      for (std::size_t p = 0; p < 2; ++p) v += kH[s][p] * (effect == Planted::kMirror ? std::conj(masses[r][p]) : masses[r][p]);
      if (effect == Planted::kCubic) v *= 1.0 / (1.0 + 0.08 * std::norm(v));  // a gain that falls with size
      run.readings.push_back(gain * v + P(n(g), n(g)));
    }
    runs.push_back(run);
  }
  return runs;
}

const ModelTest& named(const std::vector<ModelTest>& tests, const std::string& name) {
  for (const auto& t : tests) {
    if (t.name == name) return t;
  }
  throw std::runtime_error("no test " + name);
}

TEST(BalancingModelTests, EachPlantedEffectIsFoundAndCleanCampaignsFindNothing) {
  std::mt19937_64 g(5);
  int clean_findings = 0, mirror_found = 0, cubic_found = 0;
  const int campaigns = 200;
  for (int k = 0; k < campaigns; ++k) {
    for (const auto& t : test_linear_model(campaign(g, Planted::kNone, 0.01), 2)) clean_findings += t.significant;
    mirror_found += named(test_linear_model(campaign(g, Planted::kMirror, 0.01), 2), "phase sense").significant;
    cubic_found += named(test_linear_model(campaign(g, Planted::kCubic, 0.01), 2), "amplitude nonlinearity").significant;
  }
  EXPECT_LE(clean_findings, campaigns * 3 / 100);
  EXPECT_GE(mirror_found, campaigns * 95 / 100);
  EXPECT_GE(cubic_found, campaigns * 90 / 100);
  // The mirror image is named as a declared sense that is wrong.
  const auto mirror = test_linear_model(campaign(g, Planted::kMirror, 0.01), 2);
  EXPECT_NE(named(mirror, "phase sense").finding.find("count in opposite senses"), std::string::npos);
}

TEST(BalancingModelTests, ASmallCampaignSaysWhatItCannotTest) {
  std::mt19937_64 g(6);
  std::vector<BalancingRun> runs = campaign(g, Planted::kNone, 0.01);
  runs = {runs[0], runs[1], runs[4]};  // as found and one trial per plane: no degrees of freedom
  const auto tests = test_linear_model(runs, 2);
  for (const auto& t : tests) {
    EXPECT_FALSE(t.ran) << t.name;
    EXPECT_FALSE(t.needs.empty()) << t.name;
  }
}

// Runout: the rotor's own readings at two speeds, through each speed's coefficients, read one
// unbalance only when the constant reading (runout) is taken out. The rotor's own readings come
// from its unbalance u0 (a = H u0 at each speed, H scaled by the speed's gain).
TEST(BalancingModelTests, RunoutIsFoundAcrossTwoSpeedsAndNotInventedWithout) {
  std::mt19937_64 g(7);
  const P u0[2] = {std::polar(15.0, 1.3), std::polar(9.0, -0.4)};
  std::vector<P> own;
  for (std::size_t s = 0; s < kA.size(); ++s) own.push_back(kH[s][0] * u0[0] + kH[s][1] * u0[1]);
  int found = 0, invented = 0;
  for (int k = 0; k < 200; ++k) {
    for (bool planted : {false, true}) {
      std::vector<InfluenceCalibration> speeds;
      for (double gain : {1.0, 2.5}) {
        std::vector<BalancingRun> runs = campaign(g, Planted::kNone, 0.01, gain, own);
        if (planted) {
          for (auto& r : runs) r.readings[1] += std::polar(0.5, 1.0);  // a runout on sensor 1
        }
        speeds.push_back(calibrate(runs, 2));
      }
      const ModelTest t = test_runout(speeds);
      ASSERT_TRUE(t.ran);
      (planted ? found : invented) += t.significant;
    }
  }
  EXPECT_GE(found, 190);
  EXPECT_LE(invented, 10);
  EXPECT_FALSE(test_runout({}).ran);
}

}  // namespace
}  // namespace poise::estimators
