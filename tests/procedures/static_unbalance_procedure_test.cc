// The simulated static-unbalance test (Yang 2015 Sec. 5): on an ideal rig it returns the
// true unbalance within 0.1%; each instrument error moves the estimate the way the physics
// says; results are a pure function of the seed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/units.h"
#include "procedures/static_unbalance_procedure.h"

namespace poise::procedures {
namespace {

using units::kRadPerDeg;
constexpr double kG = 9.80665;

TestPlan ideal_plan(std::size_t positions) {
  TestPlan plan;
  for (std::size_t i = 0; i < positions; ++i) {
    plan.positions.push_back(2.0 * units::kPi * static_cast<double>(i) / static_cast<double>(positions));
  }
  plan.servo.inertia_estimate = 3.5e-3;
  plan.servo.kt_nominal = 0.05;
  plan.servo.current_limit = 1.0;
  plan.oscillation.rate_amplitude = 2.0 * kRadPerDeg;
  plan.oscillation.period = 4.0;
  plan.oscillation.periods = 2;
  plan.acquisition.rate_hz = 500;
  plan.acquisition.adc_bits = 24;
  plan.acquisition.adc_full_scale = 2.0;
  plan.solver.rtol = 1e-6;
  plan.solver.max_order = 2;
  plan.solver.atol_per_state = {1e-8, 1e-7, 1e-11, 1e-8, 1e-11, 1e-8, 1e-9};
  plan.gravity = kG;
  return plan;
}

GimbalTruth ideal_truth(double unbalance_kgm, double angle) {
  GimbalTruth t;
  t.disk.mass = 1.5;
  t.disk.inertia = 3.5e-3;
  t.disk.support_stiffness = 1e7;
  t.disk.support_damping = 230;
  t.disk.eccentricity = unbalance_kgm / t.disk.mass;
  t.disk.eccentricity_angle = angle;
  t.kt_true = 0.05;
  return t;
}

MeasurementResult measure(const TestPlan& plan, const GimbalTruth& truth, std::uint64_t seed = 1) {
  StaticUnbalanceWorkspace ws(plan.solver);
  sampling::RandomStream rs(seed, sampling::StreamId::kProcedure, 0);
  return run_static_unbalance_procedure(plan, truth, rs, ws);
}

TEST(StaticUnbalanceProcedure, IdealRigReturnsTheTrueUnbalance) {
  const double u = 25.81e-3 * 0.051;  // the paper's 12.91 mN*m load
  for (double angle_deg : {45.5, 200.0}) {
    const GimbalTruth truth = ideal_truth(u, angle_deg * kRadPerDeg);
    const MeasurementResult m = measure(ideal_plan(36), truth);
    const double true_torque = u * kG;
    EXPECT_NEAR(m.fit.amplitude / true_torque, 1.0, 1e-3) << angle_deg;
    EXPECT_NEAR(std::remainder(m.fit.phase - angle_deg * kRadPerDeg, 2 * units::kPi), 0.0, 1e-3);
    EXPECT_NEAR(m.fit.offset, 0.0, 1e-3 * true_torque);
    for (const auto& p : m.positions) {
      EXPECT_LT(p.max_abs_phi, 3.0 * kRadPerDeg);
      EXPECT_FALSE(p.saturated);
      EXPECT_LT(p.rms_tracking, 1e-4);
    }
    // The oscillation's mean of sin(theta + phi + eps) is J0(a) sin(theta + eps): the
    // estimate sits a^2/4 below the truth, a = A T / 2 pi.
    const double a = 2.0 * kRadPerDeg * 4.0 / (2 * units::kPi);
    EXPECT_NEAR(m.fit.amplitude / true_torque, 1.0 - a * a / 4.0, 2e-5);
  }
}

TEST(StaticUnbalanceProcedure, EighteenPositionsToo) {
  const double u = 1e-3;
  const MeasurementResult m = measure(ideal_plan(18), ideal_truth(u, 1.0));
  EXPECT_NEAR(m.fit.amplitude / (u * kG), 1.0, 1e-3);
}

TEST(StaticUnbalanceProcedure, KtErrorScalesTheEstimate) {
  GimbalTruth truth = ideal_truth(1e-3, 0.3);
  truth.kt_true = 0.05 * 1.04;  // the motor is 4% stronger than the estimate assumes
  const MeasurementResult m = measure(ideal_plan(18), truth);
  EXPECT_NEAR(m.fit.amplitude / (1e-3 * kG), 1.0 / 1.04, 1e-3);
}

TEST(StaticUnbalanceProcedure, GimbalZeroErrorShiftsThePhase) {
  TestPlan plan = ideal_plan(18);
  plan.oscillation.centre = 1.0 * kRadPerDeg;
  const MeasurementResult m = measure(plan, ideal_truth(1e-3, 0.3));
  EXPECT_NEAR(m.fit.phase, 0.3 + 1.0 * kRadPerDeg, 1e-3);
}

TEST(StaticUnbalanceProcedure, CableNeutralOffsetGoesIntoTheOffset) {
  GimbalTruth truth = ideal_truth(1e-3, 0.3);
  truth.disk.torsion_stiffness = 5e-3;
  truth.disk.torsion_zero = 2.0 * kRadPerDeg;
  truth.disk.coulomb_friction = 1.5e-3;  // symmetric: averages out over whole periods
  truth.disk.viscous_friction = 2e-4;
  const MeasurementResult m = measure(ideal_plan(18), truth);
  // The motor holds the cable at the mean angle 0: MK = k_CR (0 - phi_0).
  EXPECT_NEAR(m.fit.offset, -5e-3 * 2.0 * kRadPerDeg, 2e-6);
  EXPECT_NEAR(m.fit.amplitude / (1e-3 * kG), 1.0, 2e-3);
}

TEST(StaticUnbalanceProcedure, DeterministicForASeed) {
  TestPlan plan = ideal_plan(8);
  plan.acquisition.noise_rms = 0.01;
  plan.acquisition.offset_drift = 0.002;
  plan.acquisition.adc_bits = 12;
  plan.positioning_error = 10.0 / 3600.0 * kRadPerDeg;
  const GimbalTruth truth = ideal_truth(1e-3, 0.3);
  const MeasurementResult a = measure(plan, truth, 7), b = measure(plan, truth, 7), c = measure(plan, truth, 8);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i) EXPECT_EQ(a.positions[i].torque, b.positions[i].torque);
  EXPECT_EQ(a.fit.amplitude, b.fit.amplitude);
  EXPECT_NE(a.fit.amplitude, c.fit.amplitude);
}

TEST(StaticUnbalanceProcedure, RefusesTooFewPositions) {
  EXPECT_THROW(measure(ideal_plan(3), ideal_truth(1e-3, 0.0)), Error);
}

}  // namespace
}  // namespace poise::procedures

namespace poise::procedures {
namespace {

TEST(TestPlanPlacement, EveryPlacementVisitsEachPositionOnce) {
  for (std::size_t n : {4u, 7u, 18u, 36u}) {
    for (const char* name : {"sequential", "interleaved", "back_and_forth"}) {
      TestPlan plan;
      set_positions(plan, n, parse_placement(name));
      ASSERT_EQ(plan.positions.size(), n) << name;
      std::vector<double> sorted = plan.positions;
      std::sort(sorted.begin(), sorted.end());
      for (std::size_t k = 0; k < n; ++k) {
        EXPECT_NEAR(sorted[k], 2.0 * units::kPi * static_cast<double>(k) / static_cast<double>(n), 1e-12) << name << n;
      }
      EXPECT_TRUE(plan.sweep.empty() || plan.sweep.size() == n);
    }
  }
  TestPlan plan;
  set_positions(plan, 8, Placement::kInterleaved);  // 0, 180, 90, 270, 45, 225, 135, 315 deg
  const double expected[] = {0, 4, 2, 6, 1, 5, 3, 7};
  for (std::size_t k = 0; k < 8; ++k) EXPECT_NEAR(plan.positions[k], expected[k] * units::kPi / 4, 1e-12);
  set_positions(plan, 6, Placement::kBackAndForth);  // up on 0, 2, 4; back on 5, 3, 1
  const double bf[] = {0, 2, 4, 5, 3, 1};
  const int sweep[] = {1, 1, 1, -1, -1, -1};
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_NEAR(plan.positions[k], bf[k] * units::kPi / 3, 1e-12);
    EXPECT_EQ(plan.sweep[k], sweep[k]);
  }
  EXPECT_THROW(parse_placement("random"), Error);
}

TEST(TestPlanPlacement, TestDurationMatchesTheProcedureClock) {
  TestPlan plan = ideal_plan(12);
  plan.move_time = 3.0;
  const MeasurementResult m = measure(plan, ideal_truth(1e-3, 0.3));
  // Each position's time is the middle of its integration window.
  const OscillationConfig& o = plan.oscillation;
  const double window_mid = plan.move_time + o.settle_time + o.lead_in + 0.5 * o.periods * o.period;
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    EXPECT_NEAR(m.positions[i].time, static_cast<double>(i) * position_duration(plan) + window_mid, 1e-9);
  }
  EXPECT_NEAR(test_duration(plan), 12 * (3.0 + 1.0 + 0.5 + 2 * 4.0), 1e-12);
}

TEST(TestPlanPlacement, BackAndForthCancelsALinearDrift) {
  // An offset drifting linearly in time follows the angle in a sequential test and biases
  // the fit; going up on the even positions and back on the odd ones adds the drift to both
  // halves with opposite slopes, and it cancels to first order.
  const double u = 25.81e-3 * 0.051;
  GimbalTruth truth = ideal_truth(u, 45.5 * kRadPerDeg);
  truth.disturbances.offset_drift_rate = 2e-5;  // A/s: 1e-3 mN*m/s through K_T 0.05
  const double ideal = measure(ideal_plan(18), ideal_truth(u, 45.5 * kRadPerDeg)).fit.amplitude;
  double error[3];
  int k = 0;
  for (Placement p : {Placement::kSequential, Placement::kInterleaved, Placement::kBackAndForth}) {
    TestPlan plan = ideal_plan(18);
    set_positions(plan, 18, p);
    const MeasurementResult m = measure(plan, truth);
    error[k++] = std::abs(m.fit.amplitude - ideal);
  }
  EXPECT_GT(error[0], 5e-5);            // sequential: ~0.1 mN*m off
  EXPECT_LT(error[2], 0.1 * error[0]);  // back and forth: cancelled
  EXPECT_LT(error[1], error[0]);        // interleaved: decorrelated
  RecordProperty("errors_mNm", std::to_string(error[0] * 1e3) + " " + std::to_string(error[1] * 1e3) + " " +
                                   std::to_string(error[2] * 1e3));
}

}  // namespace
}  // namespace poise::procedures
