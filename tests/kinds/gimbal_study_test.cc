// Gimbal static-unbalance study end to end on a tiny campaign: thread-count independence,
// replay of one sample, strict files, and an ideal rig that balances to within the noise.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <tuple>
#include <nlohmann/json.hpp>

#include "model_files/gimbal_model.h"
#include "kinds/gimbal_static_unbalance/gimbal_study.h"
#include "engine/study_files/study_config.h"
#include "engine/kind_interface/study_evaluation.h"
#include "engine/results/result_io.h"
#include "engine/run/study_runner.h"
#include "engine/study_files/toml_reader.h"
#include "kinds/gimbal_static_unbalance/gimbal_sections.h"
#include "study_run_options.h"
#include "test_util.h"

using namespace poise::kinds::gimbal_static_unbalance;  // the kinds' and model files' own namespaces
using namespace poise::model_files;  // the kinds' and model files' own namespaces

namespace poise::engine {
namespace {

using nlohmann::json;
using test::TempDir;

std::string tiny_study(const TempDir& d, const std::string& extra_model_override = "") {
  const std::string text = R"([study]
name = "tiny"
kind = "gimbal_static_unbalance"
model = ")" + test::source_path("models/gimbal_simulator_yang2015.toml") + R"("

[sampling]
method = "monte_carlo"
samples = 4
seed = 3
)" + extra_model_override + R"(
[output]
block = 2

[[group]]
name = "g"
positions = 8
repeats = 1

[[group.load]]
mass = "25.81 g"
radius = "51.0 mm"
angle = "45.50 deg"

[[group.load]]
mass = "15.53 g"
radius = "35.0 mm"
angle = "270.30 deg"

[[reference]]
name = "a measured campaign's RMSE of MT_s"
output = "g_rmse_torque_mNm"
value = "0.5 mN*m"
source = "test"
role = "validation"
)";
  const std::string path = d.file("study.toml");
  test::write_text(path, text);
  return path;
}

RunOptions options(const std::string& out, int threads) { return test::quiet_run_options(out, threads); }

TEST(GimbalStudy, SamplesIdenticalForOneAndTwoThreadsAndReplay) {
  TempDir d;
  const std::string study = tiny_study(d);
  run_study(study, options(d.file("t1"), 1));
  run_study(study, options(d.file("t2"), 2));
  const std::string a = test::read_text(d.file("t1/samples.csv"));
  EXPECT_EQ(a, test::read_text(d.file("t2/samples.csv")));
  EXPECT_NE(a.find("g_rmse_torque_mNm"), std::string::npos);
  const json s = json::parse(test::read_text(d.file("t1/summary.json")));
  EXPECT_EQ(s["failures"]["count"], 0);
  ASSERT_EQ(s["references"].size(), 1u);
  EXPECT_EQ(s["references"][0]["output"], "g_rmse_torque_mNm");
  EXPECT_NEAR(s["references"][0]["reference"].get<double>(), 0.5, 1e-12);  // in the output's unit, mN*m
  EXPECT_EQ(s["references"][0]["verdict"], "undecided");  // 4 samples cannot place a 95% range
  const json r = replay_sample(study, 3, options("", 1));
  EXPECT_EQ(r["status"], "ok");
  // Row 3 of samples.csv holds the same RMSE.
  std::istringstream in(a);
  std::string line, header;
  std::getline(in, header);
  for (int k = 0; k <= 3; ++k) std::getline(in, line);
  const double rmse = r["outputs"]["g_rmse_torque_mNm"].get<double>();
  const std::string buf = poise::engine::csv_number(rmse);
  EXPECT_NE(line.find(buf), std::string::npos) << line << " vs " << buf;
}

TEST(GimbalStudy, IdealRigBalancesWithinTheNoise) {
  TempDir d;
  // Every tolerance and noise source off: the counterweight leaves only the oscillation's
  // J0 bias (a^2/4 = 1.2e-4 of the load) and the solver tolerance.
  std::string ov = "\n[overrides]\n";
  const std::pair<const char*, const char*> zeros[] = {
      {"residual_unbalance", "0 g*mm"}, {"runout", "0 um"}, {"clump_mass", "0 g"}, {"hole_radius", "0 mm"},
      {"hole_angle", "0 deg"}, {"kt_drift", "0"}, {"turntable_zero", "0 deg"}, {"gimbal_zero", "0 deg"},
      {"axis_tilt", "0 deg"}, {"counterweight_mass", "0"}, {"counterweight_radius", "0 mm"},
      {"counterweight_angle", "0 deg"}, {"kt_calibration", "0"}};
  for (const auto& [k, v] : zeros) ov.append("\"tolerances.").append(k).append(".tolerance\" = \"").append(v).append("\"\n");
  for (const char* k : {"acquisition.noise_rms", "acquisition.offset", "acquisition.offset_drift",
                        "acquisition.offset_noise"}) {
    ov.append("\"").append(k).append("\" = \"0 A\"\n");
  }
  ov += "\"turntable.positioning_error\" = \"0 deg\"\n\"rotor.coulomb_friction\" = \"0 N*m\"\n";
  ov += "\"rotor.torsion_stiffness\" = \"0 N*m/rad\"\n\"rotor.viscous_friction\" = \"0 N*m*s/rad\"\n";
  const std::string study = tiny_study(d, ov);
  run_study(study, options(d.file("run"), 2));
  const json s = json::parse(test::read_text(d.file("run/summary.json")));
  ASSERT_EQ(s["failures"]["count"], 0) << s["failures"].dump();
  // Loads of 12.9 and 5.3 mN*m: errors below 0.1% of the load.
  EXPECT_LT(s["outputs"]["g_rmse_torque_mNm"]["max"]["value"].get<double>(), 0.005);
  EXPECT_LT(s["outputs"]["g_rmse_angle_deg"]["max"]["value"].get<double>(), 0.05);
  // Residual after the counterweight: below 0.1% of the larger load's 1316 g*mm.
  EXPECT_LT(s["outputs"]["g_max_residual_gmm"]["max"]["value"].get<double>(), 1.4);
}

TEST(GimbalStudy, InterruptedRunResumesToTheSameSamples) {
  TempDir d;
  const std::string study = tiny_study(d);
  run_study(study, options(d.file("full"), 2));
  const std::string full = test::read_text(d.file("full/samples.csv"));
  // An interruption: the copy keeps the header, two samples and half of the third line.
  std::filesystem::create_directories(d.file("cut"));
  std::filesystem::copy_file(d.file("full/run.json"), d.file("cut/run.json"));
  std::size_t pos = 0;
  for (int k = 0; k < 3; ++k) pos = full.find('\n', pos) + 1;
  const std::size_t third_end = full.find('\n', pos);
  test::write_text(d.file("cut/samples.csv"), full.substr(0, pos + (third_end - pos) / 2));
  RunOptions o = options("", 1);
  o.resume = d.file("cut");
  run_study(study, o);
  EXPECT_EQ(test::read_text(d.file("cut/samples.csv")), full);
  const json a = json::parse(test::read_text(d.file("full/summary.json")));
  const json b = json::parse(test::read_text(d.file("cut/summary.json")));
  EXPECT_NEAR(a["outputs"]["g_rmse_torque_mNm"]["mean"]["value"].get<double>(),
              b["outputs"]["g_rmse_torque_mNm"]["mean"]["value"].get<double>(), 1e-8);
  EXPECT_EQ(b["provenance"]["resumed_after_sample"], 2);
  // A changed study refuses to resume.
  test::write_text(study, test::read_text(study) + "\n# edited\n");
  EXPECT_THROW(run_study(study, o), Error);
}

TEST(GimbalStudy, StrictGroupsAndScopes) {
  TempDir d;
  std::string text = test::read_text(tiny_study(d));
  text = test::replace_once(text, "positions = 8", "positions = 2");
  test::write_text(d.file("bad.toml"), text);
  try {
    validate_study(d.file("bad.toml"));
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'group[0].positions' = 2: expected an integer from 4 to 3600"),
              std::string::npos) << e.what();
  }
  try {
    load_gimbal_model(test::source_path("models/gimbal_simulator_yang2015.toml"),
                      {{"tolerances.runout.scope", "sample"}});
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'tolerances.runout.scope' = \"sample\": expected one of \"unit\", \"test\""),
              std::string::npos) << e.what();
  }
  try {
    load_gimbal_model(test::source_path("models/gimbal_simulator_yang2015.toml"),
                      {{"oscillation.rate_amplitude", "6 deg/s"}});
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("an oscillation within the stated swing_range +-3 deg"), std::string::npos) << e.what();
  }
}

TEST(GimbalStudy, StudyKeysChangeTheTestPlan) {
  TempDir d;
  StudyConfig cfg = load_study(tiny_study(d));
  // Study keys go to the groups; model keys are returned.
  StudyConfig c = cfg;
  const auto rest = apply_study_overrides(
      c, {{"group.positions", "18"}, {"group.g.placement", "back_and_forth"}, {"rotor.mass", "2 kg"}});
  ASSERT_EQ(rest.size(), 1u);
  EXPECT_EQ(rest.at("rotor.mass"), "2 kg");
  EXPECT_EQ(gimbal_sections(c).groups[0].positions, 18u);
  EXPECT_EQ(gimbal_sections(c).groups[0].placement, "back_and_forth");
  for (const auto& [key, value, expected] :
       std::vector<std::tuple<std::string, std::string, std::string>>{
           {"group.positions", "3", "an integer in [4, 3600]"},
           {"group.positions", "18.5", "an integer in [4, 3600]"},
           {"group.placement", "random", "one of \"sequential\""},
           {"group.h.positions", "18", "the name of a [[group]]: g"},
           {"group.speed", "1", "a study key group[.<name>].positions"}}) {
    StudyConfig bad = cfg;
    try {
      apply_study_overrides(bad, {{key, value}});
      FAIL() << key;
    } catch (const ValidationError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
  // The test time follows the plan: 12 positions of 5 s move, 1 s settle, 0.5 s lead-in, 2 x 4 s.
  const McResult e = evaluate_study(cfg, {{"group.positions", "12"}}, 1, 3, 1);
  EXPECT_NEAR(e.values[e.index("g_test_time_min")].at(0), 12 * 14.5 / 60.0, 1e-12);
}

// The rig's disk from its geometry (models/simulator_disk_yang2015.toml, issue 8): each
// sample's disk unbalance is the face wedge's w R / (8 t) (plus the hole positions' little),
// towards the thick side; the mass follows the thickness; the run replays.
TEST(GimbalStudy, DiskFromGeometryCarriesTheWedgeUnbalance) {
  TempDir d;
  const std::string path =
      tiny_study(d, "\n[overrides]\n\"geometry.disk_model\" = \"simulator_disk_yang2015.toml\"\n");
  const StudyConfig cfg = load_study(path);
  const GimbalModel model = load_gimbal_model(cfg.model_path, cfg.overrides);
  ASSERT_TRUE(model.disk_geometry.has_value());
  EXPECT_TRUE(model.disk_geometry->nominal.clumps.empty());  // the loads are the groups'
  const GimbalStudy study(cfg, model, 4, 3);
  auto col = [&](const std::string& name) {
    const auto& n = study.input_names();
    const auto it = std::find(n.begin(), n.end(), name);
    EXPECT_NE(it, n.end()) << name;
    return static_cast<std::size_t>(it - n.begin());
  };
  auto ws = study.make_workspace();
  const double r = 0.065, t = 0.012;
  for (std::size_t i = 0; i < 4; ++i) {
    SampleResult s;
    study.compute(i, *ws, s);
    ASSERT_TRUE(s.ok) << s.message;
    const double w = s.inputs[col("disk_wedge_mm")] * 1e-3, mass = s.inputs[col("disk_mass_g")] * 1e-3;
    const double u = s.inputs[col("disk_unbalance_gmm")] * 1e-6;
    EXPECT_NEAR(u, mass * w * r / (8 * t), 0.03 * mass * w * r / (8 * t) + 0.1e-6) << i;
    if (u > 0.5e-6) {
      EXPECT_NEAR(std::remainder(s.inputs[col("disk_unbalance_angle_deg")] - s.inputs[col("disk_wedge_angle_deg")], 360.0),
                  0.0, 10.0) << i;
    }
    EXPECT_NEAR(mass / model.disk_nominal_mass, 1.0 + s.inputs[col("disk_thickness_dev_mm")] * 1e-3 / t, 1e-4) << i;
    SampleResult again;
    study.compute(i, *ws, again);
    EXPECT_EQ(again.outputs, s.outputs);
  }
  // Off by default; a missing file is refused with the key.
  EXPECT_FALSE(load_gimbal_model(cfg.model_path).disk_geometry.has_value());
  try {
    load_gimbal_model(cfg.model_path, {{"geometry.disk_model", "no_such_disk.toml"}});
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("geometry.disk_model"), std::string::npos) << e.what();
  }
}

// The kind's fast model (StudyKind::fast_model: each position's mean current from the load
// averaged over whole periods of the reference) against the full one on the shipped study
// the test-plan optimization runs, with the same draws: per sample, the torque error differs
// by far less than it varies from sample to sample, and the test time and b agree.
TEST(GimbalStudy, FastModelFollowsTheFullModel) {
  StudyConfig cfg = load_study(test::source_path("studies/gimbal_unbalance_mc.toml"));
  for (const std::string positions : {"18", "36"}) {
    const std::map<std::string, std::string> o{{"group.positions", positions}};
    const McResult full = evaluate_study(cfg, o, 12, 5, 2);
    StudyConfig fast_cfg = cfg;
    fast_cfg.fast_model = true;
    const McResult fast = evaluate_study(fast_cfg, o, 12, 5, 2);
    ASSERT_EQ(full.failures, 0u);
    ASSERT_EQ(fast.failures, 0u);
    for (const std::string out : {"g_rmse_torque_mNm", "g_rmse_angle_deg", "g_test_time_min", "g_max_swing_deg"}) {
      const auto& a = full.values[full.index(out)];
      const auto& b = fast.values[fast.index(out)];
      double largest = 0.0, mean = 0.0, spread = 0.0;
      for (std::size_t i = 0; i < a.size(); ++i) {
        largest = std::max(largest, std::abs(a[i] - b[i]));
        mean += a[i] / static_cast<double>(a.size());
      }
      for (double v : a) spread += (v - mean) * (v - mean) / static_cast<double>(a.size() - 1);
      spread = std::sqrt(spread);
      std::printf("%s positions %s: largest |fast - full| %.3e, full mean %.4g, std %.3g\n", out.c_str(),
                  positions.c_str(), largest, mean, spread);
      if (out == "g_test_time_min") {
        EXPECT_EQ(largest, 0.0);
      } else if (out == "g_max_swing_deg") {
        EXPECT_LT(largest, 0.005);  // the tracking error the fast model leaves out (deg)
      } else {
        EXPECT_LT(largest, 0.01 * spread) << out;  // errors: far inside their sample-to-sample spread
      }
    }
  }
}

}  // namespace
}  // namespace poise::engine
