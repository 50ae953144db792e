// Every kind answers its question through the one engine path: a user's study with
// [[requirement]] tables (and a [[sweep]]) writes samples.h5, "requirements", "answer" and
// "sweeps"; the terminal's last line before the report's path is the answer, the report opens
// with it, and `--require` exits 3 unless every requirement is met.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_util.h"

namespace poise {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using test::read_text;
using test::source_path;
using test::TempDir;

// `path` in double quotes, as a TOML string (built by append: gcc 12 warns, wrongly, of
// overlapping copies in "\"" + std::string).
std::string quoted(const std::string& path) {
  std::string q = "\"";
  q.append(path).append("\"");
  return q;
}

// A user's copy of a shipped study (its model by absolute path) with `extra` appended.
std::string user_study(const TempDir& dir, const std::string& shipped, const std::string& model,
                       const std::string& extra) {
  std::string text = read_text(source_path("studies/" + shipped + ".toml"));
  text = test::replace_once(text, quoted("../models/" + model), quoted(source_path("models/" + model)));
  const std::string path = dir.file(shipped + "_user.toml");
  test::write_text(path, text + "\n" + extra);
  return path;
}

std::string requirement(const std::string& output, const std::string& statistic, const std::string& at_most) {
  return "[[requirement]]\noutput = \"" + output + "\"\nstatistic = \"" + statistic + "\"\nat_most = \"" + at_most +
         "\"\nconfidence = 0.9\n";
}

// The last non-empty lines of a text.
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) out.push_back(line);
  }
  return out;
}

// Runs the study and checks what every kind's answered run holds; returns its summary.
json run_and_check(const TempDir& dir, const std::string& study, const std::string& extra_args,
                   std::size_t requirements) {
  const std::string out = dir.file("run");
  const auto r = test::run_poise(dir, "run '" + study + "' --threads 2 --quiet --no-plots --out '" + out + "' " + extra_args);
  EXPECT_EQ(r.status, 0) << r.err;
  const json s = json::parse(read_text(out + "/summary.json"));
  EXPECT_TRUE(fs::exists(out + "/samples.h5"));
  EXPECT_TRUE(s.contains("samples_h5"));
  EXPECT_EQ(s["requirements"].size(), requirements);
  for (const auto& v : s["requirements"]) {
    EXPECT_TRUE(v["verdict"] == "met" || v["verdict"] == "not met" || v["verdict"] == "undecided") << v.dump();
    for (const char* key : {"output", "statistic", "limit", "value", "bound", "confidence", "verdict"}) {
      EXPECT_TRUE(v.contains(key)) << key;
    }
    EXPECT_TRUE(v["limit"].contains("value") && v["limit"].contains("unit"));
  }
  const std::string answer = s["answer"].get<std::string>();
  EXPECT_FALSE(answer.empty());
  // The terminal: the answer, then the report's path, last.
  const auto lines = lines_of(r.out);
  EXPECT_GE(lines.size(), 2u);
  if (lines.size() >= 2) {
    EXPECT_EQ(lines[lines.size() - 2], answer);
    EXPECT_EQ(lines.back().rfind("report: ", 0), 0u);
  }
  // The report opens with it (first thing after the title).
  const std::string html = read_text(out + "/report.html");
  const auto h1 = html.find("</h1>");
  const auto at = html.find("class='answer'");
  EXPECT_NE(at, std::string::npos);
  EXPECT_LT(h1, at);
  EXPECT_EQ(html.find("<h2", h1), html.find("<h2", at)) << "a section comes before the answer";
  // Units as the kind declares them, and a description for every output.
  for (const auto& [name, o] : s["outputs"].items()) {
    EXPECT_TRUE(o.contains("unit")) << name;
    EXPECT_TRUE(o.contains("description")) << name;
  }
  return s;
}

TEST(StudyAnswers, GimbalStudyWithRequirementsAndSweep) {
  TempDir dir;
  const std::string study = user_study(
      dir, "gimbal_unbalance_mc", "gimbal_simulator_yang2015.toml",
      requirement("g_rmse_torque_mNm", "p95", "50 mN*m") + requirement("g_max_residual_gmm", "p50", "1e6 g*mm") +
          "[[sweep]]\nparameter = \"oscillation.rate_amplitude\"\nvalues = [\"1.5 deg/s\", \"2 deg/s\"]\nsamples = 2\n");
  const json s = run_and_check(dir, study, "--samples 3", 2);
  ASSERT_EQ(s["sweeps"].size(), 1u);
  EXPECT_EQ(s["sweeps"][0]["parameter"], "oscillation.rate_amplitude");
  ASSERT_EQ(s["sweeps"][0]["points"].size(), 2u);
  for (const auto& p : s["sweeps"][0]["points"]) {
    EXPECT_TRUE(p["outputs"].contains("g_rmse_torque_mNm"));
    EXPECT_EQ(p["outputs"]["g_rmse_torque_mNm"]["unit"], "mN*m");
    EXPECT_EQ(p["requirements"].size(), 2u);
  }
  EXPECT_EQ(s["outputs"]["g_rmse_torque_mNm"]["unit"], "mN*m");
  EXPECT_EQ(s["outputs"]["g_test_time_min"]["unit"], "min");
}

// Contributions of a procedure kind: every toleranced slot, those drawn per test included, set
// to zero in turn in its own unit; without the K_T drift the torque error collapses.
TEST(StudyAnswers, GimbalContributionsIncludePerTestTolerances) {
  TempDir dir;
  std::string study = user_study(dir, "gimbal_unbalance_mc", "gimbal_simulator_yang2015.toml", "");
  test::write_text(study, test::replace_once(read_text(study), "[output]\nblock = 8", "[output]\nblock = 8\ncontribution_samples = 2"));
  const json s = run_and_check(dir, study, "--samples 2", 0);
  std::map<std::string, json> by;
  for (const auto& c : s["contributions"]) by[c["without"].get<std::string>()] = c;
  ASSERT_TRUE(by.count("(nothing: all tolerances)") && by.count("tolerances.kt_drift")) << s["contributions"].dump();
  const auto p95 = [](const json& c) { return c["outputs"]["g_rmse_torque_mNm"]["p95"]["value"].get<double>(); };
  EXPECT_LT(p95(by["tolerances.kt_drift"]), 0.5 * p95(by["(nothing: all tolerances)"]));
}

TEST(StudyAnswers, RequireExitsThreeWhenNotMet) {
  TempDir dir;
  const std::string study = user_study(dir, "gimbal_unbalance_mc", "gimbal_simulator_yang2015.toml",
                                       requirement("g_rmse_torque_mNm", "mean", "1e-9 mN*m"));
  const std::string out = dir.file("run");
  const auto r = test::run_poise(dir, "run '" + study + "' --samples 2 --threads 2 --quiet --no-plots --require --out '" +
                                          out + "'");
  EXPECT_EQ(r.status, 3) << r.err;
  const json s = json::parse(read_text(out + "/summary.json"));
  EXPECT_EQ(s["requirements"][0]["verdict"], "not met");
  EXPECT_EQ(s["answer"].get<std::string>().rfind("NOT met", 0), 0u);
  // Without --require the same run exits 0; --require on a study without requirements is refused.
  const auto plain = test::run_poise(dir, "run '" + study + "' --samples 2 --threads 2 --quiet --no-plots");
  EXPECT_EQ(plain.status, 0) << plain.err;
  const auto none = test::run_poise(dir, "run '" + source_path("studies/gimbal_unbalance_mc.toml") +
                                             "' --samples 2 --quiet --no-plots --require --out '" + dir.file("none") + "'");
  EXPECT_EQ(none.status, 2);
  EXPECT_NE(none.err.find("states no requirement"), std::string::npos) << none.err;
  EXPECT_FALSE(fs::exists(dir.file("none")));
}

TEST(StudyAnswers, BalancingMachineStudyWithRequirements) {
  TempDir dir;
  const std::string study = user_study(dir, "wang2014_balancing_mc", "balancing_machine_wang2014.toml",
                                       requirement("hard_bearing_ratio", "p95", "100") +
                                           requirement("omega1_Hz", "mean", "1 Hz"));
  const json s = run_and_check(dir, study, "--samples 2", 2);
  EXPECT_EQ(s["requirements"][1]["verdict"], "not met");  // a first mode below 1 Hz: no such machine
  EXPECT_EQ(s["outputs"]["omega1_Hz"]["unit"], "Hz");
}

TEST(StudyAnswers, PlatformStudyWithRequirements) {
  TempDir dir;
  std::string study = user_study(dir, "platform_balancing_sequence", "platform_three_gimbal.toml",
                                 requirement("initial_outer_torque_max_mNm", "p50", "1e9 mN*m"));
  // Its shafting LOS comes from the seeker study beside it.
  test::write_text(study, test::replace_once(read_text(study), quoted("los_seeker_wang2011.toml"),
                                             quoted(source_path("studies/los_seeker_wang2011.toml"))));
  const json s = run_and_check(dir, study, "--samples 1", 1);
  EXPECT_EQ(s["outputs"]["initial_outer_torque_max_mNm"]["unit"], "mN*m");
}

TEST(StudyAnswers, RequirementOnAnUnknownOutputIsRefusedWithItsLine) {
  TempDir dir;
  const std::string study = user_study(dir, "gimbal_unbalance_mc", "gimbal_simulator_yang2015.toml",
                                       requirement("g_rmse_torque_Nm", "p95", "1 mN*m"));
  const auto r = test::run_poise(dir, "validate '" + study + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("requirement.output"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("g_rmse_torque_mNm"), std::string::npos) << r.err;  // the outputs it could name
}

TEST(StudyAnswers, GeometryStudyRunsTheOnePathWithSweepsAndResume) {
  TempDir dir;
  const std::string base = user_study(dir, "geometry_mass_properties", "simulator_disk_yang2015.toml",
                                      requirement("mass_ray_error_pct", "max", "50 %"));
  // The geometry kinds run through the engine's one path: a sweep of a model key, with every
  // requirement judged at each value, as for the other kinds.
  const std::string study = dir.file("sweep.toml");
  test::write_text(study, read_text(base) + "\n[[sweep]]\nparameter = \"disk.thickness\"\nvalues = [\"10 mm\", \"14 mm\"]\n"
                                            "samples = 2\n");
  const json s = run_and_check(dir, study, "--samples 3", 1);
  EXPECT_EQ(s["outputs"]["mass_ray_error_pct"]["unit"], "%");
  ASSERT_EQ(s["sweeps"].size(), 1u);
  ASSERT_EQ(s["sweeps"][0]["points"].size(), 2u);
  const double thin = s["sweeps"][0]["points"][0]["outputs"]["mass_g"]["mean"]["value"].get<double>();
  const double thick = s["sweeps"][0]["points"][1]["outputs"]["mass_g"]["mean"]["value"].get<double>();
  EXPECT_GT(thick, thin * 1.2) << "a thicker disk is heavier";
  for (const auto& p : s["sweeps"][0]["points"]) EXPECT_EQ(p["requirements"].size(), 1u);
  EXPECT_TRUE(s["details"]["nominal"].contains("closed_form_check"));
  // --resume keeps the samples a run has: the rows come back byte for byte.
  const std::string csv = read_text(dir.file("run") + "/samples.csv");
  const auto r = test::run_poise(dir, "run --resume '" + dir.file("run") + "' --threads 1 --quiet --no-plots");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(read_text(dir.file("run") + "/samples.csv"), csv);
}

}  // namespace
}  // namespace poise
