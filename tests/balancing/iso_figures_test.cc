// ISO 21940-21 figures from a proving-rotor campaign (balancing/iso_figures.h): on a machine
// that reads the linear model exactly, URR is 1 and U_mar is the bare rotor's residual unbalance
// (the spread of |U_0 + T e^{i phi}| over the positions); with noise, their 95% intervals hold
// those values at their level (U_mar's conservatively).
#include "balancing/iso_figures.h"

#include <gtest/gtest.h>

#include <random>

namespace poise::balancing {
namespace {

using estimators::Phasor;

const Phasor kH[3][2] = {{std::polar(0.08, 1.0), std::polar(0.02, -0.5)},
                         {std::polar(0.05, 2.5), std::polar(0.06, 0.3)},
                         {std::polar(0.01, -2.0), std::polar(0.09, 1.7)}};
const Phasor kResidual[2] = {std::polar(0.4, 0.0), std::polar(0.3, 0.0)};  // g at the radius: the proving rotor's

BalancingCampaign proving_campaign(std::mt19937_64& g, double noise) {
  BalancingCampaign c;
  c.sensors = {"a", "b", "c"};
  c.planes = {"p1", "p2"};
  c.plane_radius = {0.1, 0.1};
  c.plane_holes = {0, 0};
  c.plane_first_hole = {0.0, 0.0};
  std::normal_distribution<double> n(0.0, noise);
  std::vector<std::pair<std::vector<Phasor>, bool>> runs = {{{0.0, 0.0}, false},
                                                            {{std::polar(10.0, 0.3), 0.0}, false},
                                                            {{0.0, std::polar(10.0, 2.0)}, false},
                                                            {{std::polar(10.0, 4.0), std::polar(10.0, 5.0)}, false},
                                                            {{std::polar(8.0, 1.0), std::polar(8.0, 3.0)}, false}};
  for (int k = 0; k < 4; ++k) {  // the U_mar test: 5 g in both planes through 0, 90, 180, 270 deg
    const Phasor t = std::polar(5.0, k * M_PI / 2.0);
    runs.push_back({{t, t}, true});
  }
  for (std::size_t r = 0; r < runs.size(); ++r) {
    for (int repeat = 0; repeat < 2; ++repeat) {
      estimators::BalancingRun run;
      run.name = "run " + std::to_string(r);
      run.declared = r;
      run.masses = runs[r].first;
      run.check = runs[r].second;
      for (int s = 0; s < 3; ++s) {
        Phasor v = 0.0;
        for (int p = 0; p < 2; ++p) v += kH[s][p] * (kResidual[p] + runs[r].first[static_cast<std::size_t>(p)]);
        run.readings.push_back(v + Phasor(n(g), n(g)));
      }
      c.runs.push_back(run);
    }
    c.umar_run.push_back(runs[r].second);
  }
  c.declared_runs = runs.size();
  return c;
}

TEST(IsoFigures, AnExactMachineHasURRofOneAndUmarOfTheRotorsResidual) {
  std::mt19937_64 g(1);
  const BalancingCampaign c = proving_campaign(g, 0.0);
  const auto a = analyse_campaign(c);
  const IsoFigures iso = iso_figures(c, a.speeds.front());
  ASSERT_EQ(iso.urr.size(), 8u);  // 4 check runs, each with a test mass in both planes
  for (const auto& f : iso.urr) EXPECT_NEAR(f.urr, 1.0, 1e-9);
  ASSERT_EQ(iso.umar.size(), 2u);
  for (std::size_t p = 0; p < 2; ++p) {
    EXPECT_EQ(iso.umar[p].positions, 4u);
    EXPECT_EQ(iso.umar[p].unit, "g mm");
    EXPECT_NEAR(iso.umar[p].umar, std::abs(kResidual[p]) * 100.0, 1e-6);  // g at 100 mm
  }
}

TEST(IsoFigures, IntervalsHoldTheMachinesFiguresWithNoise) {
  std::mt19937_64 g(2);
  int urr_in = 0, urr_all = 0, umar_in = 0, umar_all = 0;
  for (int k = 0; k < 200; ++k) {
    const BalancingCampaign c = proving_campaign(g, 0.01);
    const auto a = analyse_campaign(c);
    const IsoFigures iso = iso_figures(c, a.speeds.front());
    for (const auto& f : iso.urr) {
      ASSERT_TRUE(f.lower && f.upper);
      urr_in += *f.lower <= 1.0 && 1.0 <= *f.upper;
      ++urr_all;
    }
    for (std::size_t p = 0; p < iso.umar.size(); ++p) {
      const double truth = std::abs(kResidual[p]) * 100.0;
      umar_in += *iso.umar[p].lower <= truth && truth <= *iso.umar[p].upper;
      ++umar_all;
    }
  }
  // URR's interval holds exactly when the region's circle holds T: the region's coverage (95%,
  // measured 94.7% of 1600 here, 1.4 standard errors of a binomial below); U_mar's is wider.
  EXPECT_GE(urr_in, urr_all * 93 / 100);
  EXPECT_GE(umar_in, umar_all * 95 / 100);
}

}  // namespace
}  // namespace poise::balancing
