// Gimbal static-unbalance study end to end on a tiny campaign: thread-count independence,
// replay of one sample, strict files, and an ideal rig that balances to within the noise.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "studies/gimbal_model.h"
#include "studies/study_runner.h"
#include "studies/toml_reader.h"
#include "test_util.h"

namespace poise::studies {
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
paper_rmse_torque = "0.5 mN*m"

[[group.load]]
mass = "25.81 g"
radius = "51.0 mm"
angle = "45.50 deg"

[[group.load]]
mass = "15.53 g"
radius = "35.0 mm"
angle = "270.30 deg"
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
  EXPECT_EQ(s["paper_comparison"].size(), 1u);
  const json r = replay_sample(study, 3, options("", 1));
  EXPECT_EQ(r["status"], "ok");
  // Row 3 of samples.csv holds the same RMSE.
  std::istringstream in(a);
  std::string line, header;
  std::getline(in, header);
  for (int k = 0; k <= 3; ++k) std::getline(in, line);
  const double rmse = r["outputs"]["g_rmse_torque_mNm"].get<double>();
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", rmse);
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
    EXPECT_NE(std::string(e.what()).find("an oscillation within +-3 deg"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace poise::studies
