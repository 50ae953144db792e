// Time-series diagnosis of one turntable position on records made by the engine's own
// simulator with an effect switched on that the base model does not declare: it must find
// the effect unasked, improve the torque estimate, and stay quiet on clean records.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"
#include "core/units.h"
#include "estimators/oscillation_diagnosis.h"
#include "procedures/static_unbalance_procedure.h"

namespace poise::estimators {
namespace {

using procedures::GimbalTruth;
using procedures::RecordSample;
using procedures::TestPlan;
using units::kRadPerDeg;
constexpr double kG = 9.80665;
constexpr double kKt = 0.05;

TestPlan plan_one_position(double theta) {
  TestPlan plan;
  plan.positions = {theta, theta + 1.0, theta + 2.0, theta + 3.0};  // the test needs 4; record the first
  plan.servo.inertia_estimate = 3.5e-3;
  plan.servo.kt_nominal = kKt;
  plan.servo.current_limit = 1.0;
  plan.servo.bandwidth_hz = 20;
  plan.servo.damping = 0.7;
  plan.oscillation.rate_amplitude = 2.0 * kRadPerDeg;
  plan.oscillation.period = 4.0;
  plan.oscillation.periods = 2;
  plan.acquisition.rate_hz = 500;
  plan.acquisition.noise_rms = 0.002;
  plan.acquisition.adc_bits = 16;
  plan.acquisition.adc_full_scale = 2.0;
  plan.solver.rtol = 1e-6;
  plan.solver.max_order = 2;
  plan.solver.atol_per_state = {1e-8, 1e-7, 1e-11, 1e-8, 1e-11, 1e-8, 1e-9};
  plan.gravity = kG;
  return plan;
}

GimbalTruth truth_with(double cogging, double drift_rate) {
  GimbalTruth t;
  t.disk.mass = 1.5;
  t.disk.inertia = 3.5e-3;
  t.disk.support_stiffness = 1e7;
  t.disk.support_damping = 230;
  t.disk.viscous_friction = 2e-4;
  t.disk.coulomb_friction = 1.5e-3;
  t.disk.eccentricity = 25.81e-3 * 0.051 / 1.5;
  t.disk.eccentricity_angle = 45.5 * kRadPerDeg;
  t.disk.cogging_torque = cogging;
  t.disk.cogging_order = 180;  // 36 slots, 20 poles: lcm 180 detents per turn
  t.disk.cogging_phase = 0.5 * units::kPi;
  t.kt_true = kKt;
  t.disturbances.offset_drift_rate = drift_rate;
  return t;
}

OscillationRecord record(const TestPlan& plan, const GimbalTruth& truth, std::uint64_t seed) {
  procedures::StaticUnbalanceWorkspace ws(plan.solver);
  sampling::RandomStream rs(seed, sampling::StreamId::kProcedure, 0);
  std::vector<RecordSample> raw;
  procedures::run_static_unbalance_procedure(plan, truth, rs, ws, 0, &raw);
  OscillationRecord r;
  for (const auto& s : raw) {
    r.t.push_back(s.t);
    r.current.push_back(s.current);
    r.phi.push_back(s.phi);
  }
  return r;
}

OscillationOptions options() {
  OscillationOptions o;
  o.kt = kKt;
  return o;
}

TEST(OscillationDiagnosis, FindsUndeclaredCoggingAndImprovesTheTorque) {
  const double theta = 0.3;
  const TestPlan plan = plan_one_position(theta);
  const GimbalTruth truth = truth_with(0.3e-3, 0.0);
  const OscillationDiagnosis d = diagnose_oscillation(record(plan, truth, 1), options());
  ASSERT_FALSE(d.effects.empty());
  EXPECT_EQ(d.effects[0].name, "cogging");
  // Orders N and N +- 1 differ by only 0.044 rad across the +-1.27 deg swing.
  EXPECT_NEAR(d.effects[0].order, 180, 2);
  EXPECT_NEAR(d.effects[0].params[0].value, 0.3e-3, 3 * d.effects[0].params[0].se + 0.02e-3);
  // The position's true unbalance torque (J0 factor of the +-1.27 deg swing included).
  const double a = 2.0 * kRadPerDeg * 4.0 / (2 * units::kPi);
  const double truth_torque = 1.5 * kG * truth.disk.eccentricity * std::sin(theta + truth.disk.eccentricity_angle) *
                              (1.0 - a * a / 4.0);
  const double err_before = std::abs(d.torque_eq21 - truth_torque);
  const double err_after = std::abs(d.torque_after.value - truth_torque);
  // Over the swing +-a cogging averages to T_cog J0(N a) sin(N phi_c + psi): J0(4.0) = -0.40.
  EXPECT_GT(err_before, 0.08e-3);
  EXPECT_LT(err_after, 0.3 * err_before) << "before " << err_before << " after " << err_after;
  EXPECT_LT(d.rmse_after, 0.8 * d.rmse_before);
  // Coulomb asymmetry is reported as not identifiable at one position, not silently skipped.
  bool reported = false;
  for (const auto& [name, why] : d.not_identifiable) reported = reported || name == "coulomb_asymmetry";
  EXPECT_TRUE(reported);
}

TEST(OscillationDiagnosis, AddingTheFoundCoggingToTheModelReproducesTheRecord) {
  const TestPlan plan = plan_one_position(0.3);
  const GimbalTruth truth = truth_with(0.3e-3, 0.0);
  const OscillationRecord measured = record(plan, truth, 1);
  const OscillationDiagnosis d = diagnose_oscillation(measured, options());
  ASSERT_FALSE(d.effects.empty());
  // The simulation model before (no cogging) and after (the cogging found) against the record.
  GimbalTruth before = truth_with(0.0, 0.0), after = before;
  after.disk.cogging_order = d.effects[0].order;
  after.disk.cogging_torque = d.effects[0].params[0].value;
  after.disk.cogging_phase = d.effects[0].params[1].value;
  auto rms_diff = [&](const GimbalTruth& model) {
    const OscillationRecord sim = record(plan, model, 1);  // same noise draws as the record
    double s = 0;
    for (std::size_t k = 0; k < sim.current.size(); ++k) s += std::pow(sim.current[k] - measured.current[k], 2);
    return std::sqrt(s / static_cast<double>(sim.current.size()));
  };
  const double rms_before = rms_diff(before), rms_after = rms_diff(after);
  EXPECT_LT(rms_after, 0.2 * rms_before) << "current RMS difference " << rms_before << " -> " << rms_after << " A";
}

TEST(OscillationDiagnosis, JitteredStampsAndGapsAreUsedAsTheyAre) {
  // The record as a PC logger would keep it: a third of the rows lost at random (steps of one,
  // two or three sampling periods) and a gap of 250 rows; the values at the rows kept are the
  // record's own, at their own times (no more than two rows lost in a row).
  const TestPlan plan = plan_one_position(0.3);
  const GimbalTruth truth = truth_with(0.3e-3, 0.0);
  const OscillationRecord full = record(plan, truth, 1);
  OscillationRecord logged;
  std::mt19937_64 rng(5);
  std::bernoulli_distribution lost(1.0 / 3.0);
  const std::size_t gap_from = full.t.size() / 2, gap_to = gap_from + 250;
  int lost_in_a_row = 0;
  for (std::size_t k = 0; k < full.t.size(); ++k) {
    if (k >= gap_from && k < gap_to) continue;
    if (k > 0 && lost_in_a_row < 2 && lost(rng)) {  // steps of up to three periods: jitter, not gaps
      ++lost_in_a_row;
      continue;
    }
    lost_in_a_row = 0;
    logged.t.push_back(full.t[k]);
    logged.current.push_back(full.current[k]);
    logged.phi.push_back(full.phi[k]);
    logged.lines.push_back(k + 2);
  }
  const OscillationDiagnosis a = diagnose_oscillation(full, options());
  const OscillationDiagnosis b = diagnose_oscillation(logged, options());
  EXPECT_EQ(a.gaps, 0u);
  EXPECT_EQ(b.gaps, 1u);
  double widest = 0.0;  // the gap, widened by the rows lost beside it
  for (std::size_t k = 1; k < logged.t.size(); ++k) widest = std::max(widest, logged.t[k] - logged.t[k - 1]);
  EXPECT_DOUBLE_EQ(b.gap_largest, widest);
  EXPECT_GE(widest, full.t[gap_to] - full.t[gap_from - 1] - 1e-12);
  ASSERT_FALSE(b.effects.empty());
  EXPECT_EQ(b.effects[0].name, "cogging");
  EXPECT_NEAR(b.effects[0].order, 180, 2);
  const double se = b.effects[0].params[0].se;
  EXPECT_NEAR(b.effects[0].params[0].value, a.effects[0].params[0].value, 3 * se);
  EXPECT_NEAR(b.torque_after.value, a.torque_after.value, 3 * b.torque_after.se);
}

TEST(OscillationDiagnosis, FindsAnOffsetDrift) {
  const TestPlan plan = plan_one_position(1.0);
  const OscillationDiagnosis d = diagnose_oscillation(record(plan, truth_with(0.0, 1e-4), 2), options());
  ASSERT_EQ(d.effects.size(), 1u);
  EXPECT_EQ(d.effects[0].name, "offset_drift");
  EXPECT_NEAR(d.effects[0].params[0].value, kKt * 1e-4, 3 * d.effects[0].params[0].se);
}

TEST(OscillationDiagnosis, QuietOnCleanRecords) {
  const TestPlan plan = plan_one_position(0.7);
  int false_positives = 0;
  const int runs = 40;
  for (int k = 0; k < runs; ++k) {
    const OscillationDiagnosis d = diagnose_oscillation(record(plan, truth_with(0.0, 0.0), 100 + k), options());
    false_positives += d.effects.empty() ? 0 : 1;
  }
  // Family-wise alpha 0.05: expect ~2 of 40; allow the binomial 97.5% bound (5 of 40).
  EXPECT_LE(false_positives, 5) << false_positives << " of " << runs;
}

TEST(OscillationDiagnosis, RefusesBadRecords) {
  OscillationRecord r;
  r.t = {0, 1, 2};
  r.current = {0, 0, 0};
  r.phi = {0, 0, 0};
  EXPECT_THROW(diagnose_oscillation(r, options()), Error);
  OscillationOptions o = options();
  o.kt = 0;
  EXPECT_THROW(diagnose_oscillation(r, o), Error);
}

TEST(OscillationDiagnosis, ErrorsNameTheFileAndLine) {
  OscillationRecord r;
  r.file = "rec.csv";
  for (int k = 0; k < 200; ++k) {
    r.t.push_back(k * 1e-3 - (k == 121 ? 2e-3 : 0.0));
    r.current.push_back(0.1 * std::sin(0.1 * k));
    r.phi.push_back(0.01 * std::sin(0.05 * k));
    r.lines.push_back(static_cast<std::size_t>(k) + 2);
  }
  const auto message = [&](const OscillationOptions& o) {
    try {
      diagnose_oscillation(r, o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(options()).find("rec.csv:123: time 0.119 s goes back from 0.12 s"), std::string::npos)
      << message(options());
  OscillationOptions o = options();
  o.kt = 1e308;
  EXPECT_NE(message(o).find("rec.csv: the torque constant K_T = "), std::string::npos);
  EXPECT_NE(message(o).find("expected a finite value in (0, 1e6) N*m/A"), std::string::npos);
}

}  // namespace
}  // namespace poise::estimators
