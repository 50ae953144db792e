// The three-gimbal balancing campaign: an ideal platform balances to within the measurement
// noise (and, noise off, to within the procedure's own bias), the order matters, samples are
// the same for any thread count and on replay, and the study and model files are strict.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <nlohmann/json.hpp>

#include "kinds/platform_balancing/platform_model.h"
#include "kinds/platform_balancing/platform_shafting.h"
#include "kinds/platform_balancing/platform_study.h"
#include "kinds/platform_balancing/platform_study_config.h"
#include "engine/study_files/study_config.h"
#include "engine/results/result_io.h"
#include "engine/run/study_runner.h"
#include "engine/study_files/toml_reader.h"
#include "study_run_options.h"
#include "test_util.h"

using namespace poise::kinds::platform_balancing;  // the kinds' and model files' own namespaces

namespace poise::engine {
namespace {

using nlohmann::json;
using test::TempDir;

// Every tolerance but the centroids off; `noise` keeps the acquisition's noise.
std::string ideal_overrides(bool noise) {
  std::string ov = "\n[overrides]\n\"oscillation.periods\" = \"1\"\n";
  const std::pair<const char*, const char*> zeros[] = {
      {"kt_calibration", "0"}, {"kt_drift", "0"}, {"lock_error", "0 deg"}, {"fixture_tilt", "0 deg"},
      {"turntable_zero", "0 deg"}, {"gimbal_zero", "0 deg"}, {"counterweight_mass", "0"},
      {"counterweight_radius", "0 mm"}, {"counterweight_angle", "0 deg"}, {"counterweight_plane", "0 mm"}};
  for (const auto& [k, v] : zeros) ov.append("\"tolerances.").append(k).append(".tolerance\" = \"").append(v).append("\"\n");
  if (!noise) {
    for (const char* k : {"acquisition.noise_rms", "acquisition.offset", "acquisition.offset_drift", "acquisition.offset_noise"}) {
      ov.append("\"").append(k).append("\" = \"0 A\"\n");
    }
    ov += "\"turntable.positioning_error\" = \"0 deg\"\n";
  }
  return ov;
}

std::string tiny_study(const TempDir& d, const std::string& overrides = "\n[overrides]\n\"oscillation.periods\" = \"1\"\n",
                       const std::string& orders = R"(["inner,middle,outer"])") {
  const std::string text = R"([study]
name = "tiny_platform"
kind = "platform_balancing"
model = ")" + test::source_path("models/platform_three_gimbal.toml") + R"("

[sampling]
method = "sobol"
samples = 4
seed = 7

[platform]
orders = )" + orders + R"(
positions = 8
outer_min = "-180 deg"
outer_max = "90 deg"
outer_points = 4
middle_min = "-30 deg"
middle_max = "30 deg"
middle_points = 3
inner_min = "-30 deg"
inner_max = "30 deg"
inner_points = 3
acceleration_x = "0 m/s^2"
acceleration_y = "98 m/s^2"
acceleration_z = "0 m/s^2"

[platform.profile]
duration = "0.2 s"
time_step = "1 ms"
manoeuvre_x = "0 m/s^2"
manoeuvre_y = "98 m/s^2"
manoeuvre_z = "0 m/s^2"
onset = "0.05 s"
rise_time = "20 ms"

[[platform.profile.vibration]]
amplitude_x = "0 m/s^2"
amplitude_y = "0 m/s^2"
amplitude_z = "20 m/s^2"
frequency = "40 Hz"
)" + overrides + R"(
[output]
block = 2
)";
  const std::string path = d.file("study.toml");
  test::write_text(path, text);
  return path;
}

// One campaign per order on sample `i`; residual perpendicular first moment per axis (kg m)
// after it, and the as-built one.
struct CampaignOutcome {
  std::array<double, 3> before{}, after{};
  std::array<std::array<double, 3>, 3> after_by_order{};
};
CampaignOutcome campaign(const std::string& study_path, std::size_t i) {
  const StudyConfig cfg = load_study(study_path);
  const PlatformStudy study(cfg, load_platform_model(cfg.model_path, cfg.overrides), cfg.samples, cfg.seed);
  auto ws = study.make_workspace();
  const PlatformDraws d = study.draws(i);
  const models::Platform built = study.as_built(d);
  CampaignOutcome out;
  out.before = study.residual(built).perpendicular;
  for (std::size_t o = 0; o < platform_sections(cfg).platform.orders.size(); ++o) {
    const CampaignResult c = study.run_campaign(i, built, d, platform_sections(cfg).platform.orders[o], *ws);
    out.after_by_order[o] = study.residual(c.platform).perpendicular;
  }
  out.after = out.after_by_order[0];
  return out;
}

TEST(PlatformStudy, IdealPlatformNoiseOffBalancesToTheProceduresBias) {
  TempDir d;
  const CampaignOutcome c = campaign(tiny_study(d, ideal_overrides(false)), 1);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_GT(c.before[k], 50e-6) << k;  // tens of g*mm as built
    // Noise off, no placement errors: only the oscillation's J0 bias, the cable and
    // friction and the solver tolerance remain; below 1% of the as-built unbalance.
    EXPECT_LT(c.after[k], 0.01 * c.before[k]) << "axis " << k << ": " << c.after[k] * 1e6 << " g*mm";
  }
}

TEST(PlatformStudy, LockingErrorsBarelyMatterInsideOut) {
  // Locking errors of 1 deg (3 sigma), noise off: the gimbals that carry the tested one only
  // tilt its axis (second order); those it carries are already balanced inside-out, so
  // turning them changes nothing to first order.
  TempDir d;
  std::string ov = ideal_overrides(false);
  ov = test::replace_once(ov, "\"tolerances.lock_error.tolerance\" = \"0 deg\"", "\"tolerances.lock_error.tolerance\" = \"1 deg\"");
  const CampaignOutcome c = campaign(tiny_study(d, ov), 1);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_LT(c.after[k], 0.02 * c.before[k]) << k;
}

TEST(PlatformStudy, IdealPlatformWithNoiseBalancesWithinTheNoise) {
  TempDir d;
  const CampaignOutcome c = campaign(tiny_study(d, ideal_overrides(true)), 2);
  // Noise of one axis test: 4.4 mA position-to-position offset noise, 2 mA white and a
  // 1 mA/position drift, about 5 mA per position, times K_T; 8 positions fit MT_s to
  // sigma ~ s_pos sqrt(2/8). Divided by g: 7.6 (inner), 13 (middle), 20 g*mm (outer).
  const std::array<double, 3> sigma{0.03 * 5e-3 * 0.5 / 9.80665, 0.05 * 5e-3 * 0.5 / 9.80665, 0.08 * 5e-3 * 0.5 / 9.80665};
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_LT(c.after[k], 5.0 * sigma[k]) << "axis " << k << ": " << c.after[k] * 1e6 << " g*mm vs sigma " << sigma[k] * 1e6;
    EXPECT_LT(c.after[k], 0.5 * c.before[k]) << k;
  }
}

TEST(PlatformStudy, OutsideInLeavesTheOuterAxesUnbalanced) {
  TempDir d;
  const CampaignOutcome c =
      campaign(tiny_study(d, ideal_overrides(false), R"(["inner,middle,outer", "outer,middle,inner"])"), 1);
  // Outer first: the middle and inner counterweights placed afterwards (and their offsets
  // along their own axes, which the outer axis sees) unbalance the outer axis again.
  EXPECT_GT(c.after_by_order[1][2], 10.0 * c.after_by_order[0][2]);
  EXPECT_GT(c.after_by_order[1][1], 5.0 * c.after_by_order[0][1]);
  // The inner axis is the same whatever the order: its test sees the inner gimbal alone.
  EXPECT_NEAR(c.after_by_order[1][0], c.after_by_order[0][0], 1e-12);
}

TEST(PlatformStudy, SamplesIdenticalForOneAndTwoThreadsAndReplay) {
  TempDir d;
  const std::string study = tiny_study(d);
  run_study(study, test::quiet_run_options(d.file("t1"), 1));
  run_study(study, test::quiet_run_options(d.file("t2"), 2));
  const std::string a = test::read_text(d.file("t1/samples.csv"));
  EXPECT_EQ(a, test::read_text(d.file("t2/samples.csv")));
  const json s = json::parse(test::read_text(d.file("t1/summary.json")));
  EXPECT_EQ(s["failures"]["count"], 0) << s["failures"].dump();
  EXPECT_GT(s["outputs"]["imo_los_max_arcsec"]["mean"]["value"].get<double>(), 0.0);
  EXPECT_FALSE(s["details"]["los_budget"].empty());
  const json r = replay_sample(study, 3, test::quiet_run_options("", 1));
  ASSERT_EQ(r["status"], "ok");
  std::istringstream in(a);
  std::string line;
  for (int k = 0; k <= 4; ++k) std::getline(in, line);  // header, then samples 0..3
  const std::string buf = poise::engine::csv_number(r["outputs"]["imo_outer_residual_gmm"].get<double>());
  EXPECT_NE(line.find(buf), std::string::npos) << line << " vs " << buf;
}

TEST(PlatformStudy, StrictStudyAndModelFiles) {
  TempDir d;
  const std::string text = test::read_text(tiny_study(d, "", R"(["inner,inner,outer"])"));
  test::write_text(d.file("bad.toml"), text);
  try {
    load_study(d.file("bad.toml"));
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'platform.orders' = \"inner,inner,outer\": expected each of inner, middle, outer once"),
              std::string::npos)
        << e.what();
  }
  try {
    load_platform_model(test::source_path("models/platform_three_gimbal.toml"), {{"inner.counterweight_radius", "25"}});
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("inner.counterweight_radius"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("missing unit"), std::string::npos) << e.what();
  }
  const std::string model = test::read_text(test::source_path("models/platform_three_gimbal.toml"));
  test::write_text(d.file("model.toml"), test::replace_once(model, "lock_angle = \"0 deg\"\nnotes = \"\"\"Detector",
                                                             "lock_angle = \"0 deg\"\nlock_torque = \"1 N*m\"\nnotes = \"\"\"Detector"));
  try {
    load_platform_model(d.file("model.toml"));
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("inner.lock_torque"), std::string::npos) << e.what();
  }
}


// [platform.shafting] takes any study through the kind interface: its output in an angle and
// the same error in px, by the units the study declares; the pixel's angle is their ratio
// (the Wang 2011 seeker's 18.75 arcsec). Outputs of the wrong dimension or none are refused.
TEST(PlatformStudy, ShaftingLineFromAnyStudyByItsDeclaredUnits) {
  TempDir d;
  const std::string base = test::read_text(tiny_study(d));
  const auto with_shafting = [&](const std::string& keys) {
    test::write_text(d.file("shafting.toml"), base + "\n[platform.shafting]\nstudy = \"" +
                                                  test::source_path("studies/los_seeker_wang2011.toml") +
                                                  "\"\nsamples = 64\n" + keys);
    return load_study(d.file("shafting.toml"));
  };
  const ShaftingLos line = compute_shafting_los(with_shafting(""), 2);
  ASSERT_EQ(line.los_max_arcsec.size(), 64u);
  EXPECT_NEAR(line.pixel_arcsec, 18.75, 1e-9);
  EXPECT_TRUE(std::is_sorted(line.los_max_arcsec.begin(), line.los_max_arcsec.end()));
  const auto refused = [&](const std::string& keys, const std::string& what) {
    try {
      check_shafting_study(with_shafting(keys));
      ADD_FAILURE() << keys << ": no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  refused("output = \"los_max_px\"\n", "output = \"los_max_px\": the study");
  refused("output = \"los_max_px\"\n", "gives it in px, expected an angle");
  refused("pixel_output = \"los_rms_arcsec\"\n", "gives it in arcsec, expected px");
  refused("output = \"los_peak\"\n", "has no such output (its outputs: los_max_arcsec");
}

// The model notes' stiffness figures are the model's own: least disturbance stiffness of each
// axis' loop (0.81 J w_n^2 near w_n / 2), and the poles and crossover the notes state.
TEST(PlatformStudy, LoopFiguresOfTheModelNotes) {
  TempDir d;
  const StudyConfig cfg = load_study(tiny_study(d));
  const PlatformStudy study(cfg, load_platform_model(cfg.model_path, cfg.overrides), cfg.samples, cfg.seed);
  const double stated[3] = {20.4, 45.8, 117.0};  // inner, middle, outer (N m/rad), model notes
  for (std::size_t k = 0; k < 3; ++k) {
    models::StabilizationLoop l = study.model().stabilization;
    l.inertia = study.axis_inertia()[k];
    const double wn = 2 * std::numbers::pi * 40.0;
    EXPECT_NEAR(l.least_disturbance_stiffness().first / stated[k], 1.0, 0.005) << k;
    EXPECT_NEAR(l.least_disturbance_stiffness().first / (l.inertia * wn * wn), 0.806, 0.005) << k;
    EXPECT_NEAR(l.crossover_hz(), 59.0, 0.3);
  }
}

// The old key is refused with the new one named; rate_pi reads crossover.
TEST(PlatformStudy, StabilizationKeysAndRateLoop) {
  TempDir d;
  const std::string model = test::read_text(test::source_path("models/platform_three_gimbal.toml"));
  test::write_text(d.file("old.toml"), test::replace_once(model, "natural_frequency = \"40 Hz\"", "bandwidth = \"40 Hz\""));
  try {
    load_platform_model(d.file("old.toml"));
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("stabilization.bandwidth"), std::string::npos) << m;
    EXPECT_NE(m.find("did you mean natural_frequency"), std::string::npos) << m;
  }
  test::write_text(d.file("rate.toml"),
                   test::replace_once(model, "loop = \"position_pid\"\nnatural_frequency = \"40 Hz\"\ndamping = 0.7",
                                      "loop = \"rate_pi\"\ncrossover = \"40 Hz\""));
  const PlatformModel rate = load_platform_model(d.file("rate.toml"));
  EXPECT_EQ(rate.stabilization.type, models::LoopType::kRatePi);
  EXPECT_NEAR(rate.stabilization.frequency_hz, 40.0, 1e-12);
  // A rate loop without an integral ratio has no position stiffness: refused.
  test::write_text(d.file("rate0.toml"), test::replace_once(test::read_text(d.file("rate.toml")), "integral_ratio = 0.2",
                                                             "integral_ratio = 0"));
  try {
    load_platform_model(d.file("rate0.toml"));
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("stabilization.integral_ratio"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("a ratio > 0 for loop = \"rate_pi\""), std::string::npos) << e.what();
  }
  // A rate loop with the PID's keys: damping is unknown there.
  test::write_text(d.file("mixed.toml"), test::replace_once(model, "loop = \"position_pid\"", "loop = \"rate_pi\"\ncrossover = \"40 Hz\""));
  EXPECT_THROW(load_platform_model(d.file("mixed.toml")), ValidationError);
}

// Same platform, same residual: with the position integrator a still carrier leaves no LOS
// error (gravity is taken out); the rate loop holds c . g / K_p, constant over the profile.
TEST(PlatformStudy, RateLoopHoldsTheGravityError) {
  TempDir d;
  const std::string still = "\n[overrides]\n\"oscillation.periods\" = \"1\"\n";
  std::string text = test::read_text(tiny_study(d, still));
  text = test::replace_once(text, "manoeuvre_y = \"98 m/s^2\"", "manoeuvre_y = \"0 m/s^2\"");
  text = test::replace_once(text, "amplitude_z = \"20 m/s^2\"", "amplitude_z = \"0 m/s^2\"");
  test::write_text(d.file("still.toml"), text);
  const StudyConfig cfg = load_study(d.file("still.toml"));
  PlatformModel pid_model = load_platform_model(cfg.model_path, cfg.overrides);
  PlatformModel rate_model = pid_model;
  rate_model.stabilization.type = models::LoopType::kRatePi;
  const PlatformStudy pid(cfg, pid_model, cfg.samples, cfg.seed), rate(cfg, rate_model, cfg.samples, cfg.seed);
  const models::Platform built = pid.as_built(pid.draws(0));
  const PlatformStudy::Residual rp = pid.residual(built), rr = rate.residual(built);
  EXPECT_EQ(rp.los_max, 0.0);
  EXPECT_GT(rr.los_max, 1e-7);
  EXPECT_NEAR(rr.los_rms, rr.los_max, 1e-12 * rr.los_max);
  // The residual over the angle grid includes the lock angles' value.
  for (std::size_t k = 0; k < 3; ++k) EXPECT_GE(rp.perpendicular_grid_max[k], rp.perpendicular[k] * (1 - 1e-12));
}

}  // namespace
}  // namespace poise::engine
