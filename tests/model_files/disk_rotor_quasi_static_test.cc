// The gimbal measurement's fast formulations (procedures/static_unbalance_procedure.h,
// models/disk_rotor.h): quasi-static supports against the full 7-state model at tight
// tolerances; the window's noise drawn in distribution against the instrument's per-sample
// path (same law, and the main random stream untouched, so a recorded position replays);
// the saturation flag on both paths; the model key [rotor] supports and its errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/units.h"
#include "engine/study_files/toml_reader.h"
#include "model_files/gimbal_model.h"
#include "models/disk_rotor.h"
#include "procedures/static_unbalance_procedure.h"
#include "test_util.h"

using namespace poise::model_files;  // the kinds' and model files' own namespaces

namespace poise::procedures {
namespace {

using units::kRadPerDeg;
constexpr double kClump = 25.81e-3, kRadius = 0.051;

const model_files::GimbalModel& yang_model() {
  static const model_files::GimbalModel m =
      model_files::load_gimbal_model(test::source_path("models/gimbal_simulator_yang2015.toml"));
  return m;
}

// The rig with the paper's 12.91 mN*m load at 45.5 deg (as bench/gimbal_bench.cc).
GimbalTruth loaded_truth(const model_files::GimbalModel& m) {
  GimbalTruth t;
  t.disk = m.rotor;
  t.disk.mass = m.rotor.mass + kClump;
  t.disk.inertia = m.rotor.inertia + kClump * kRadius * kRadius;
  t.disk.eccentricity = kClump * kRadius / t.disk.mass;
  t.disk.eccentricity_angle = 45.5 * kRadPerDeg;
  t.kt_true = m.plan.servo.kt_nominal;
  return t;
}

TestPlan plan_of(const model_files::GimbalModel& m, std::size_t n, Supports supports, double tighten = 1.0) {
  TestPlan p = m.plan;
  set_positions(p, n, Placement::kSequential);
  p.supports = supports;
  p.solver.rtol /= tighten, p.solver.atol /= tighten;
  for (double& a : p.solver.atol_per_state) a /= tighten;
  return p;
}

MeasurementResult measure(const TestPlan& plan, const GimbalTruth& truth, std::uint64_t seed, int record_position = -1,
                          std::vector<RecordSample>* record = nullptr) {
  StaticUnbalanceWorkspace ws(plan.solver);
  sampling::RandomStream rs(seed, sampling::StreamId::kProcedure, 0);
  return run_static_unbalance_procedure(plan, truth, rs, ws, record_position, record);
}

TEST(QuasiStaticSupports, RigidAxisEquationIsTheFullOneWithoutSupportAcceleration) {
  // With y'' = z'' = 0 the full phi equation reads (J + m e^2) phi'' = Q_phi: put the full
  // model at the deflection that makes y'' = z'' = 0 and compare phi''.
  models::DiskRotorParams p = loaded_truth(yang_model()).disk;
  const models::GimbalGravity g = models::gravity_in_gimbal(9.80665, 0.7);
  const double phi = 0.01, w = 0.03, torque = 4e-3;
  const double pdd = models::rigid_axis_acceleration(p, g, phi, w, torque);
  const double pa = phi + p.eccentricity_angle, m = p.mass, e = p.eccentricity;
  // F_y = -m e sin p phi'', F_z = m e cos p phi'' (y'' = z'' = 0), solved for y, z at rest.
  const double y = (m * e * std::cos(pa) * w * w + m * g.gy + m * e * std::sin(pa) * pdd) / p.support_stiffness;
  const double z = (m * e * std::sin(pa) * w * w + m * g.gz - m * e * std::cos(pa) * pdd) / p.support_stiffness;
  const auto acc = models::disk_accelerations(p, g, {phi, w, y, 0.0, z, 0.0}, torque);
  EXPECT_NEAR(acc[0], pdd, 1e-9 * std::abs(pdd));
  EXPECT_NEAR(acc[1], 0.0, 1e-9 * std::abs(pdd) * e);
  EXPECT_NEAR(acc[2], 0.0, 1e-9 * std::abs(pdd) * e);
}

TEST(QuasiStaticSupports, TorqueEstimateMatchesTheFullModelAtTightTolerance) {
  const model_files::GimbalModel& m = yang_model();
  const GimbalTruth truth = loaded_truth(m);
  const double load = kClump * kRadius * m.plan.gravity;
  const MeasurementResult full = measure(plan_of(m, 36, Supports::kDynamic, 1e4), truth, 3);
  const MeasurementResult quasi = measure(plan_of(m, 36, Supports::kQuasiStatic, 1e4), truth, 3);
  // The bar is 1e-4 of the load; the reduction's own error is ~(m e^2/J)(20/411)^2.
  std::printf("quasi-static vs dynamic at rtol 1e-8: |dMT_s| / load = %.2e, MT_s %.9f mN*m\n",
              std::abs(quasi.fit.amplitude - full.fit.amplitude) / load, full.fit.amplitude * 1e3);
  EXPECT_LT(std::abs(quasi.fit.amplitude - full.fit.amplitude) / load, 1e-5);
  EXPECT_LT(std::abs(std::remainder(quasi.fit.phase - full.fit.phase, 2 * units::kPi)), 1e-5);
  for (std::size_t i = 0; i < 36; ++i) {
    EXPECT_NEAR(quasi.positions[i].torque, full.positions[i].torque, 1e-5 * load) << i;
    EXPECT_NEAR(quasi.positions[i].max_abs_phi, full.positions[i].max_abs_phi, 1e-6 * kRadPerDeg) << i;
    EXPECT_FALSE(quasi.positions[i].saturated);
  }
  // And both estimate the load (J0 and the noise aside: within 1%).
  EXPECT_NEAR(quasi.fit.amplitude / load, 1.0, 1e-2);
}

TEST(WindowNoiseInDistribution, SameLawAsTheSampledInstrumentAndReplayable) {
  const model_files::GimbalModel& m = yang_model();
  const GimbalTruth truth = loaded_truth(m);
  // 100x the model's tolerances: the two paths integrate the window differently, and at the
  // model's rtol 1e-4 that alone moves the mean torque by up to ~1e-4 of it (~0.9 uN*m), as much
  // as the bound below; at 1e-6 what is left is the noise law under test.
  TestPlan plan = plan_of(m, 4, Supports::kQuasiStatic, 100.0);
  plan.acquisition.offset_drift = plan.acquisition.offset_noise = 0.0;  // the white noise alone
  plan.positioning_error = 0.0;
  const int n = 120;
  double s1 = 0, s2 = 0, r1 = 0, r2 = 0;
  std::vector<RecordSample> rec;
  for (int seed = 1; seed <= n; ++seed) {
    const MeasurementResult a = measure(plan, truth, static_cast<std::uint64_t>(seed));                // drawn
    const MeasurementResult b = measure(plan, truth, static_cast<std::uint64_t>(seed), 0, &rec);     // sampled
    ASSERT_EQ(rec.size(), 4000u);
    for (std::size_t i = 1; i < 4; ++i) EXPECT_EQ(a.positions[i].torque, b.positions[i].torque);  // replay
    s1 += a.positions[0].torque, s2 += a.positions[0].torque * a.positions[0].torque;
    r1 += b.positions[0].torque, r2 += b.positions[0].torque * b.positions[0].torque;
  }
  const double ma = s1 / n, mb = r1 / n;
  const double sa = std::sqrt((s2 - n * ma * ma) / (n - 1)), sb = std::sqrt((r2 - n * mb * mb) / (n - 1));
  // Mean of 4000 samples of 2 mA noise (+ ADC dither): sigma_mean = 31.6 uA -> 1.58 uN*m.
  const double lsb = 2.0 * plan.acquisition.adc_full_scale / std::ldexp(1.0, plan.acquisition.adc_bits);
  const double sigma = plan.servo.kt_nominal *
                       std::sqrt((std::pow(plan.acquisition.noise_rms, 2) + lsb * lsb / 12.0) / 4000.0);
  EXPECT_NEAR(sa / sigma, 1.0, 0.2);
  EXPECT_NEAR(sb / sigma, 1.0, 0.2);
  std::printf("window noise: means differ by %.3g N*m (bound %.3g); sd/sigma %.3f drawn, %.3f sampled\n",
              std::abs(ma - mb), 4.0 * sigma * std::sqrt(2.0 / n), sa / sigma, sb / sigma);
  EXPECT_NEAR(ma, mb, 4.0 * sigma * std::sqrt(2.0 / n));
}

TEST(WindowNoiseInDistribution, SaturationFlaggedOnBothPaths) {
  const model_files::GimbalModel& m = yang_model();
  const GimbalTruth truth = loaded_truth(m);
  for (Supports s : {Supports::kDynamic, Supports::kQuasiStatic}) {
    TestPlan plan = plan_of(m, 4, s);
    std::vector<RecordSample> rec0;
    const MeasurementResult ok = measure(plan, truth, 1, 1, &rec0);
    for (const auto& p : ok.positions) EXPECT_FALSE(p.saturated);
    plan.servo.current_limit = 0.15;  // the load needs |i| ~ 0.21 A at 0, 90, 180 and 270 deg
    std::vector<RecordSample> rec;
    const MeasurementResult clipped = measure(plan, truth, 1, 1, &rec);  // position 1 sampled, others drawn
    for (const auto& p : clipped.positions) EXPECT_TRUE(p.saturated);
  }
}

TEST(SupportsKey, ReadValidatedAndDocumented) {
  const std::string path = test::source_path("models/gimbal_simulator_yang2015.toml");
  EXPECT_EQ(model_files::load_gimbal_model(path).plan.supports, Supports::kDynamic);  // default
  EXPECT_EQ(model_files::load_gimbal_model(path, {{"rotor.supports", "quasi_static"}}).plan.supports,
            Supports::kQuasiStatic);
  try {
    model_files::load_gimbal_model(path, {{"rotor.supports", "rigid"}});
    FAIL() << "no error";
  } catch (const engine::ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'rotor.supports' = \"rigid\": expected one of \"dynamic\", \"quasi_static\""),
              std::string::npos) << e.what();
  }
  try {  // 1e5 N/m on 1.5 kg: a 41 Hz support mode against the 20 Hz servo
    model_files::load_gimbal_model(path, {{"rotor.supports", "quasi_static"}, {"rotor.support_stiffness", "1e5 N/m"}});
    FAIL() << "no error";
  } catch (const engine::ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'rotor.supports' = \"quasi_static\": expected \"dynamic\", or supports "
                                         "whose mode sqrt(support_stiffness / mass) / 2 pi = 41.09 Hz is at least 10 x "
                                         "the servo bandwidth (20 Hz)"),
              std::string::npos) << e.what();
  }
  const test::RunResult keys = test::run_poise(test::TempDir(), "keys gimbal_static_unbalance");
  EXPECT_NE(keys.out.find("supports"), std::string::npos) << keys.out;
  EXPECT_NE(keys.out.find("quasi_static"), std::string::npos) << keys.out;
}

}  // namespace
}  // namespace poise::procedures
