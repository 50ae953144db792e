// The gimbal study's honesty checks: a saturated drive or a swing past the stated range fails
// the sample with its reason (never a low estimate), the saturated share in summary.json; the
// residual after the counterweight about the bearing axis against an independent point-mass
// computation; the turntable-referenced placement cancelling the zero errors; the error
// mechanism and plausibility keys.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "kinds/gimbal_static_unbalance/counterweight_residual.h"
#include "model_files/gimbal_model.h"
#include "kinds/gimbal_static_unbalance/gimbal_sections.h"
#include "kinds/gimbal_static_unbalance/gimbal_study.h"
#include "engine/study_files/study_config.h"
#include "engine/run/study_runner.h"
#include "engine/study_files/toml_reader.h"
#include "study_run_options.h"
#include "test_util.h"

using namespace poise::kinds::gimbal_static_unbalance;  // the kinds' and model files' own namespaces
using namespace poise::model_files;  // the kinds' and model files' own namespaces

namespace poise::engine {
namespace {

using nlohmann::json;
using test::TempDir;
constexpr double kPi = 3.141592653589793;
constexpr double kDeg = kPi / 180.0;

std::string study_file(const TempDir& d, const std::string& loads, const std::string& extra = "",
                       const std::string& group_extra = "") {
  const std::string text = R"([study]
name = "honesty"
kind = "gimbal_static_unbalance"
model = ")" + test::source_path("models/gimbal_simulator_yang2015.toml") + R"("

[sampling]
method = "monte_carlo"
samples = 2
seed = 5
max_failure_share = 1.0
)" + extra + R"(
[output]
block = 1

[[group]]
name = "g"
positions = 8
)" + group_extra + loads;
  const std::string path = d.file("study.toml");
  test::write_text(path, text);
  return path;
}

std::string load(double torque_mNm, double angle_deg = 45.5) {
  const double mass_g = torque_mNm * 1e-3 / (9.80665 * 0.051) * 1e3;
  return "\n[[group.load]]\nmass = \"" + std::to_string(mass_g) + " g\"\nradius = \"51.0 mm\"\nangle = \"" +
         std::to_string(angle_deg) + " deg\"\n";
}

TEST(GimbalHonesty, LoadsBeyondTheMotorFailWithTheReason) {
  for (double torque : {55.0, 70.0}) {
    TempDir d;
    const StudyConfig cfg = load_study(study_file(d, load(torque)));
    GimbalStudy study(cfg, load_gimbal_model(cfg.model_path), cfg.samples, cfg.seed);
    const SampleResult r = study.replay(0);
    EXPECT_FALSE(r.ok) << torque << " mN*m: a " << r.outputs[0] << " mN*m RMSE estimate instead of a failure";
    EXPECT_EQ(r.message.rfind("drive saturated: group g, test 1", 0), 0u) << r.message;
    EXPECT_NE(r.message.find("(1 A, 50 mN*m at the nominal K_T)"), std::string::npos) << r.message;
    // The run records the reason and the saturated share.
    run_study(d.file("study.toml"), test::quiet_run_options(d.file("run"), 1));
    const json s = json::parse(test::read_text(d.file("run/summary.json")));
    EXPECT_EQ(s["failures"]["by_reason"]["drive saturated"], 2);
    EXPECT_EQ(s["details"]["saturated_share"]["count"], 2);
    EXPECT_DOUBLE_EQ(s["details"]["saturated_share"]["share"].get<double>(), 1.0);
    EXPECT_NE(test::read_text(d.file("run/report.html")).find("Saturated: 2 of 2"), std::string::npos);
  }
  // Inside the motor's range nothing fails, and the share says 0.
  TempDir d;
  run_study(study_file(d, load(25.0)), test::quiet_run_options(d.file("run"), 1));
  const json s = json::parse(test::read_text(d.file("run/summary.json")));
  EXPECT_EQ(s["failures"]["count"], 0);
  EXPECT_EQ(s["details"]["saturated_share"]["count"], 0);
}

TEST(GimbalHonesty, SwingPastTheStatedRangeFailsTheSample) {
  // A stated range just above the commanded 1.273 deg swing: the servo's tracking overshoot
  // (friction, the unbalance torque) carries the gimbal past it.
  TempDir d;
  const std::string path = study_file(d, load(20.0), "\n[overrides]\n\"oscillation.swing_range\" = \"1.2733 deg\"\n");
  const StudyConfig cfg = load_study(path);
  GimbalStudy study(cfg, load_gimbal_model(cfg.model_path, cfg.overrides), cfg.samples, cfg.seed);
  const SampleResult r = study.replay(0);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.message.rfind("swing out of range: group g, test 1", 0), 0u) << r.message;
  EXPECT_NE(r.message.find("leaving the test's stated range +-1.273 deg ([oscillation] swing_range)"), std::string::npos)
      << r.message;
  // A plan that does not fit in the stated range is refused at load time.
  try {
    load_gimbal_model(test::source_path("models/gimbal_simulator_yang2015.toml"), {{"oscillation.swing_range", "1 deg"}});
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("an oscillation within the stated swing_range +-1 deg"), std::string::npos)
        << e.what();
  }
}

// Gravity torque about the bearing axis of point masses (disk frame, from the geometric centre
// O; the bearing axis at -r from O) for the disk turned by theta: the largest over a turn / g.
double holding_amplitude_over_g(const std::vector<std::array<double, 3>>& masses, const std::array<double, 2>& r) {
  double largest = 0;
  for (int k = 0; k < 3600; ++k) {
    const double th = 2 * kPi * k / 3600.0;
    double torque = 0;
    for (const auto& [m, x, y] : masses) {
      // Lever arm from the bearing axis, rotated by theta; gravity along -Y: tau = m g X.
      const double px = x + r[0], py = y + r[1];
      torque += m * (px * std::cos(th) - py * std::sin(th));
    }
    largest = std::max(largest, std::abs(torque));
  }
  return largest;
}

TEST(GimbalHonesty, ResidualAboutTheBearingAxisMatchesPointMasses) {
  // Rotor 1.5 kg with its own centre 3 um off O, a 25.81 g clump at 51 mm / 45.5 deg, run-out
  // 2 um at 120 deg, and a counterweight 1% heavy and 0.7 deg off where Eq. 23 puts it.
  const double M = 1.5, cx = 3e-6 * std::cos(0.3), cy = 3e-6 * std::sin(0.3);
  const double mc = 0.02581, rc = 0.051, ac = 45.5 * kDeg;
  const std::array<double, 2> r{2e-6 * std::cos(120 * kDeg), 2e-6 * std::sin(120 * kDeg)};
  const double ux = M * cx + mc * rc * std::cos(ac), uy = M * cy + mc * rc * std::sin(ac);
  const double m_total = M + mc;
  const std::array<double, 2> s_bearing{ux + m_total * r[0], uy + m_total * r[1]};
  const double m_cw = 1.01 * std::hypot(s_bearing[0], s_bearing[1]) / 0.051;
  const double a_cw = std::atan2(s_bearing[1], s_bearing[0]) + kPi + 0.7 * kDeg;
  const auto res = residual_about_bearing_axis(s_bearing, r, m_cw, 0.051, a_cw);
  const double independent = holding_amplitude_over_g(
      {{M, cx, cy}, {mc, rc * std::cos(ac), rc * std::sin(ac)}, {m_cw, 0.051 * std::cos(a_cw), 0.051 * std::sin(a_cw)}}, r);
  EXPECT_NEAR(std::hypot(res[0], res[1]), independent, 1e-4 * independent);
  // Leaving out the run-out on the counterweight's mass (the old reference) is measurably off.
  const double about_o = std::hypot(ux + m_cw * 0.051 * std::cos(a_cw), uy + m_cw * 0.051 * std::sin(a_cw));
  EXPECT_GT(std::abs(about_o - independent), 1e-2 * independent);
}

TEST(GimbalHonesty, TurntablePlacementCancelsTheZeroErrors) {
  EXPECT_NEAR(counterweight_disk_angle("turntable", 1.0, 0.02, 0.0), 1.0 - 0.02 + kPi, 1e-15);
  EXPECT_NEAR(counterweight_disk_angle("disk_frame", 1.0, 0.02, 0.0), 1.0 + kPi, 1e-15);
  // A rig whose only error is a 2 deg gimbal zero (fixed): placed on the disk's scale, the
  // counterweight misses by 2 deg of the 25 mN*m load (2549 g*mm x 2 deg = 89 g*mm).
  TempDir d;
  std::string ov = "\n[overrides]\n\"tolerances.gimbal_zero.tolerance\" = \"2 deg\"\n"
                   "\"tolerances.gimbal_zero.distribution\" = \"fixed\"\n";
  for (const char* k : {"kt_drift", "counterweight_mass", "kt_calibration"}) {
    ov += std::string("\"tolerances.") + k + ".tolerance\" = \"0\"\n";
  }
  ov += "\"tolerances.counterweight_angle.tolerance\" = \"0 deg\"\n\"tolerances.counterweight_radius.tolerance\" = \"0 mm\"\n";
  const std::string loads = load(25.0) + "\n[[group]]\nname = \"t\"\npositions = 8\ncounterweight_placement = \"turntable\"\n" +
                            load(25.0);
  run_study(study_file(d, loads, ov, "counterweight_placement = \"disk_frame\"\n"),
            test::quiet_run_options(d.file("run"), 1));
  const json s = json::parse(test::read_text(d.file("run/summary.json")));
  const double disk = s["outputs"]["g_max_residual_gmm"]["mean"]["value"].get<double>();
  const double turn = s["outputs"]["t_max_residual_gmm"]["mean"]["value"].get<double>();
  EXPECT_NEAR(disk, 2549.0 * 2 * kDeg, 12.0);
  // Turntable placement removes the zero error; what is left is the one test's measurement
  // noise (10-20 g*mm over noise realisations), far below the 89 g*mm it cancels.
  EXPECT_LT(turn, 0.3 * disk);
  EXPECT_EQ(s["details"]["counterweight_placement"]["t"], "turntable");
}

TEST(GimbalHonesty, MechanismAndPlausibilityKeys) {
  const std::string model = test::source_path("models/gimbal_simulator_yang2015.toml");
  // The shipped model: scale_and_zero, and both calibrated tolerances past their ranges.
  const GimbalModel m = load_gimbal_model(model);
  EXPECT_EQ(m.error_mechanism, "scale_and_zero");
  EXPECT_EQ(m.unbalance_error_along.spec.dist.stddev(), 0.0);  // not drawn
  const auto w = plausibility_warnings(m);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_NE(w[0].find("needs a 36.7 K (1 sigma) magnet temperature swing"), std::string::npos) << w[0];
  EXPECT_NE(w[1].find("0.83 deg is 83 times the zero registration"), std::string::npos) << w[1];
  // additive: kt_drift and gimbal_zero are not drawn; the additive ones are, past 10 g*mm.
  const GimbalModel a = load_gimbal_model(model, {{"test_error.mechanism", "additive"}});
  EXPECT_EQ(a.kt_drift.spec.dist.stddev(), 0.0);
  EXPECT_NEAR(a.unbalance_error_along.spec.dist.stddev(), 58.5e-6, 1e-9);
  const auto wa = plausibility_warnings(a);
  ASSERT_EQ(wa.size(), 2u);
  EXPECT_NE(wa[0].find("tolerances.unbalance_error_along: 1 sigma 58.5 g*mm"), std::string::npos) << wa[0];
  try {
    load_gimbal_model(model, {{"test_error.mechanism", "scale"}});
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("test_error.mechanism"), std::string::npos) << e.what();
  }
  try {
    load_gimbal_model(model, {{"test_error.mechanism", "additive"}, {"tolerances.unbalance_error_along.scope", "unit"}});
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("the additive error is drawn anew for each test"), std::string::npos) << e.what();
  }
  try {
    load_gimbal_model(model, {{"plausibility.magnet_temperature_swing_K", "-1"}});
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("kelvin from 0 to 200 (1 sigma between tests)"), std::string::npos) << e.what();
  }
  try {
    load_gimbal_model(model, {{"plausibility.kt_temperature_coefficient_per_K", "0"}});
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("a relative change of K_T per kelvin, nonzero and below 0.1"), std::string::npos)
        << e.what();
  }
  try {
    load_gimbal_model(model, {{"counterweight.placement", "gravity"}});
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("counterweight.placement"), std::string::npos) << e.what();
  }
  // poise keys lists the new keys.
  TempDir d;
  const auto r = test::run_poise(d, "keys gimbal_static_unbalance");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* k : {"[test_error]", "mechanism               one of \"scale_and_zero\" | \"additive\" | \"both\"",
                        "placement               one of \"disk_frame\" | \"turntable\"", "swing_range", "[plausibility]",
                        "magnet_temperature_swing_K", "[tolerances.unbalance_error_along]", "counterweight_placement"}) {
    EXPECT_NE(r.out.find(k), std::string::npos) << k;
  }
}

TEST(GimbalHonesty, GroupCounterweightPlacementIsAStudyKey) {
  TempDir d;
  StudyConfig cfg = load_study(study_file(d, load(10.0)));
  apply_gimbal_study_overrides(cfg, {{"group.g.counterweight_placement", "turntable"}});
  EXPECT_EQ(gimbal_sections(cfg).groups[0].counterweight_placement, "turntable");
  try {
    apply_gimbal_study_overrides(cfg, {{"group.counterweight_placement", "gravity"}});
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("expected one of \"model\", \"disk_frame\", \"turntable\""), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace poise::engine
