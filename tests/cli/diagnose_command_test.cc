// End-to-end tests of `poise diagnose`: runs the built executable on the paper's Table 1, on a
// copy with an injected 2nd harmonic and on bad input; checks the JSON keys, the text, the
// --out folder (diagnosis.json, report.html, plot.svg when gnuplot exists) and exit statuses.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <sstream>
#include <string>

#include "engine/results/result_io.h"
#include "test_util.h"

namespace {

using poise::test::RunResult;
using poise::test::run_poise;

std::set<std::string> keys(const nlohmann::json& j) {
  std::set<std::string> k;
  for (const auto& [key, value] : j.items()) k.insert(key);
  return k;
}

const std::string kTable1 = poise::test::source_path("data/yang2015/table1_loading_test_36pt.csv");
const std::string kLoad = " --load-torque '12.91 mN*m' --load-angle '45.5 deg'";

TEST(DiagnoseCommand, JsonForTable1HasExactlyTheDocumentedKeys) {
  poise::test::TempDir dir;
  RunResult r = run_poise(dir, "diagnose '" + kTable1 + "' --json");
  ASSERT_EQ(r.status, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(keys(j),
            (std::set<std::string>{"answer", "file", "time_column", "sweep_column", "max_harmonic", "alpha", "tested",
                                   "effects", "rmse_before", "rmse_after", "estimate_before",
                                   "estimate_after", "unit", "n_points",
                                   "estimate_selected_model", "plan", "omnibus", "ambiguous",
                                   "collinearity", "not_identifiable", "notes"}));
  EXPECT_EQ(keys(j.at("omnibus")), (std::set<std::string>{"p_value", "unexplained_structure",
                                                          "where", "message", "tests"}));
  EXPECT_EQ(j.at("omnibus").at("tests").size(), 6u);
  EXPECT_FALSE(j.at("omnibus").at("message").get<std::string>().empty());  // never silent
  EXPECT_EQ(j.at("not_identifiable").at(0).at("name"), "turntable_angle_scale");
  EXPECT_EQ(j.at("collinearity").size(), 9u);  // harmonics 2..6, drift, K_T drift, step,
                                                // exponential drift (no sweep column)
  const std::set<std::string> estimate_keys{"amplitude",    "phase_deg",    "offset",
                                            "se_amplitude", "se_phase_deg", "se_offset"};
  EXPECT_EQ(keys(j.at("estimate_before")), estimate_keys);
  EXPECT_EQ(keys(j.at("estimate_after")), estimate_keys);
  EXPECT_EQ(j.at("unit"), "mN*m");
  EXPECT_EQ(j.at("n_points"), 36);
  // The least-squares fit of Table 1 (see fit_command_test.cc).
  EXPECT_NEAR(j.at("estimate_before").at("amplitude").get<double>(), 12.4747, 1e-4);
  EXPECT_NEAR(j.at("estimate_before").at("phase_deg").get<double>(), 42.4290, 1e-4);
  EXPECT_NEAR(j.at("rmse_before").get<double>(), 0.22512, 1e-5);
  // Table 1 holds nothing beyond Eq. 22 at alpha = 0.05 (its largest residual, 20 deg, has a
  // Bonferroni p of 0.11).
  EXPECT_TRUE(j.at("effects").empty()) << j.at("effects").dump();

  r = run_poise(dir, "diagnose '" + kTable1 + "' --json" + kLoad);
  ASSERT_EQ(r.status, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_EQ(keys(j), (std::set<std::string>{"answer", "file", "time_column", "sweep_column", "max_harmonic", "alpha",
                                            "tested", "effects", "rmse_before", "rmse_after",
                                            "estimate_before", "estimate_after", "unit", "n_points",
                                            "estimate_selected_model", "plan", "omnibus",
                                            "ambiguous", "collinearity", "not_identifiable",
                                            "notes", "load", "error_before", "error_after"}));
  EXPECT_EQ(keys(j.at("load")), (std::set<std::string>{"torque", "angle_deg"}));
  EXPECT_NEAR(j.at("load").at("torque").get<double>(), 12.91, 1e-12);
  EXPECT_NEAR(j.at("load").at("angle_deg").get<double>(), 45.5, 1e-12);
  EXPECT_EQ(keys(j.at("error_before")), (std::set<std::string>{"amplitude", "phase_deg"}));
  EXPECT_NEAR(j.at("error_before").at("amplitude").get<double>(), 12.4747 - 12.91, 1e-4);
  EXPECT_NEAR(j.at("error_before").at("phase_deg").get<double>(), 42.4290 - 45.5, 1e-4);
}

TEST(DiagnoseCommand, InjectedSecondHarmonicIsDiagnosedInTextAndJson) {
  poise::test::TempDir dir;
  std::istringstream in(poise::test::read_text(kTable1));
  std::string line, csv;
  std::getline(in, line);
  csv = line + "\n";
  while (std::getline(in, line)) {
    const double theta = std::stod(line.substr(0, line.find(','))) * std::numbers::pi / 180.0;
    const double torque = std::stod(line.substr(line.find(',') + 1));
    csv += line.substr(0, line.find(',')) + "," + std::to_string(torque + std::sin(2.0 * theta)) +
           "\n";
  }
  const std::string data = dir.file("table1_with_h2.csv");
  poise::test::write_text(data, csv);
  RunResult r = run_poise(dir, "diagnose '" + data + "' --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_FALSE(j.at("effects").empty()) << r.out;
  const auto& e = j.at("effects")[0];
  EXPECT_EQ(keys(e), (std::set<std::string>{"name", "title", "order", "params", "p_value", "p_adjusted",
                                            "delta_bic", "causes", "shift_se", "r_first_harmonic",
                                            "moves_estimate", "estimate_note", "family"}));
  EXPECT_EQ(e.at("family"), "harmonic");
  // Table 1 is one sweep in row order: time follows angle, so the 2nd harmonic is reported
  // with correlated noise as the other reading.
  EXPECT_FALSE(e.at("moves_estimate").get<bool>());
  ASSERT_EQ(j.at("ambiguous").size(), 1u) << j.at("ambiguous").dump();
  EXPECT_EQ(j.at("ambiguous")[0].at("readings").size(), 2u);
  EXPECT_NE(j.at("ambiguous")[0].at("plan").get<std::string>().find("randomise"),
            std::string::npos);
  EXPECT_EQ(e.at("name"), "harmonic");
  EXPECT_EQ(e.at("order"), 2);
  EXPECT_EQ(keys(e.at("params")), (std::set<std::string>{"amplitude", "phase_deg"}));
  EXPECT_EQ(keys(e.at("params").at("amplitude")), (std::set<std::string>{"value", "se", "unit"}));
  const double amp = e.at("params").at("amplitude").at("value");
  EXPECT_LT(std::abs(amp - 1.0), 3.0 * e.at("params").at("amplitude").at("se").get<double>());
  EXPECT_LT(j.at("rmse_after").get<double>(), j.at("rmse_before").get<double>());

  r = run_poise(dir, "diagnose '" + data + "'" + kLoad);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("1. harmonic 2: amplitude = "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("causes: Anisotropic elastic sag"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Ambiguous finding 1: harmonic 2 and correlated noise"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("Omnibus check of the final residual: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Collinearity under this plan"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  time_drift: r1 "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Not identifiable from one test: turntable_angle_scale"),
            std::string::npos);
  EXPECT_NE(r.out.find("Candidates tested in the last round, not added:"), std::string::npos);
  EXPECT_NE(r.out.find("direction_offset: not examined: the table has no sweep column"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("Error against the known load 12.91 mN*m at 45.5 deg"), std::string::npos)
      << r.out;
}

TEST(DiagnoseCommand, StudyClosesTheLoopWithTheEffectInTheSimulationModel) {
  poise::test::TempDir dir;
  std::istringstream in(poise::test::read_text(kTable1));
  std::string line, csv;
  std::getline(in, line);
  csv = line + "\n";
  while (std::getline(in, line)) {
    const double theta = std::stod(line.substr(0, line.find(','))) * std::numbers::pi / 180.0;
    const double torque = std::stod(line.substr(line.find(',') + 1));
    csv += line.substr(0, line.find(',')) + "," + std::to_string(torque + std::sin(2.0 * theta)) +
           "\n";
  }
  const std::string data = dir.file("table1_with_h2.csv");
  poise::test::write_text(data, csv);
  const std::string study = poise::test::source_path("studies/gimbal_unbalance_mc.toml");
  RunResult r = run_poise(dir, "diagnose '" + data + "' --json --study '" + study +
                                   "' --study-samples 4");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out).at("closed_loop");
  const double t2 = std::stod(j.at("overrides").at("disturbances.harmonic2_torque").get<std::string>());
  EXPECT_NEAR(t2, 1e-3, 0.2e-3);  // the injected 1 mN*m, in N*m
  bool fit_rmse = false;
  for (const auto& o : j.at("outputs")) {
    if (o.at("name") != "g_mean_fit_rmse_mNm") continue;
    fit_rmse = true;
    // The simulated fit residual with the 2nd harmonic in the model approaches the measured.
    EXPECT_GT(o.at("mean_with").get<double>(), 2.0 * o.at("mean_without").get<double>());
    EXPECT_NEAR(o.at("mean_with").get<double>(), j.at("measured_rmse").get<double>(), 0.2);
  }
  EXPECT_TRUE(fit_rmse) << j.dump();
  EXPECT_NE(j.at("sentence").get<std::string>().find("With these effects in the model"),
            std::string::npos);

  r = run_poise(dir, "diagnose '" + data + "' --study '" +
                         poise::test::source_path("studies/los_seeker_wang2011.toml") + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("study kind 'seeker_los': its model takes no effect measured in a test table (kinds whose "
                       "models do: gimbal_static_unbalance)"),
            std::string::npos)
      << r.err;
}

TEST(DiagnoseCommand, OutWritesJsonReportAndPlotAndRefusesToOverwrite) {
  poise::test::TempDir dir;
  const std::string out = dir.file("diag");
  RunResult r = run_poise(dir, "diagnose '" + kTable1 + "' --out '" + out + "'" + kLoad);
  ASSERT_EQ(r.status, 0) << r.err;
  namespace fs = std::filesystem;
  ASSERT_TRUE(fs::exists(out + "/diagnosis.json"));
  const nlohmann::json j = nlohmann::json::parse(poise::test::read_text(out + "/diagnosis.json"));
  EXPECT_TRUE(j.contains("error_after"));
  const std::string html = poise::test::read_text(out + "/report.html");
  EXPECT_NE(html.find("<h2 id='findings'>Findings</h2>"), std::string::npos);
  EXPECT_NE(html.find("No effect beyond Eq. 22 was found"), std::string::npos);
  // The answer first, the same sentence as diagnosis.json's and the terminal's last line.
  const std::string answer = j.at("answer").get<std::string>();
  EXPECT_EQ(answer.rfind("No effect beyond Eq. 22 was found in the", 0), 0u) << answer;
  EXPECT_LT(html.find("class='answer'"), html.find("id='findings'"));
  EXPECT_NE(html.find(poise::engine::html_escape(answer)), std::string::npos);
  EXPECT_NE(r.out.find(answer + "\n\nreport: "), std::string::npos) << r.out;
  EXPECT_NE(html.find("against the known load 12.91 mN*m at 45.5 deg"), std::string::npos);
  EXPECT_TRUE(fs::exists(out + "/plot.gp"));
  EXPECT_TRUE(fs::exists(out + "/plot.dat"));
  // The residuals in measurement order: Table 1 has no time_s, so by row; a header and 36 rows.
  const std::string by_time = poise::test::read_text(out + "/plot_time.dat");
  EXPECT_EQ(by_time.rfind("# row residual_before residual_after", 0), 0u) << by_time;
  EXPECT_EQ(std::count(by_time.begin(), by_time.end(), '\n'), 37);
  if (std::system("command -v gnuplot >/dev/null 2>&1") == 0) {
    ASSERT_TRUE(fs::exists(out + "/plot.svg"));
    EXPECT_NE(poise::test::read_text(out + "/plot.svg").find("<svg"), std::string::npos);
    EXPECT_NE(html.find("<svg"), std::string::npos);  // inline: the page is one file
  } else {
    EXPECT_NE(html.find("gnuplot could not be started"), std::string::npos);  // the real reason
  }
  EXPECT_NE(r.out.find("report: " + out + "/report.html"), std::string::npos) << r.out;

  const std::string before = poise::test::read_text(out + "/diagnosis.json");
  r = run_poise(dir, "diagnose '" + kTable1 + "' --out '" + out + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("already holds diagnosis.json"), std::string::npos) << r.err;
  EXPECT_EQ(poise::test::read_text(out + "/diagnosis.json"), before);
}

TEST(DiagnoseCommand, BadInputGivesStatus2WithLineAndColumn) {
  poise::test::TempDir dir;
  const std::string bad = dir.file("bad.csv");
  poise::test::write_text(
      bad, poise::test::replace_once(poise::test::read_text(kTable1), "15.77", "1S.77"));
  RunResult r = run_poise(dir, "diagnose '" + bad + "' --json");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(r.err.find(bad + ":6: column 'torque_mNm': cell '1S.77' is not a finite number"),
            std::string::npos)
      << r.err;

  r = run_poise(dir, "diagnose '" + kTable1 + "' --load-torque '12.91 mm' --load-angle '45 deg'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--load-torque '12.91 mm'"), std::string::npos) << r.err;
  r = run_poise(dir, "diagnose '" + kTable1 + "' --load-torque '12.91 mN*m'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("go together"), std::string::npos) << r.err;
  r = run_poise(dir, "diagnose '" + kTable1 + "' --noise '-0.2 mN*m'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--noise '-0.2 mN*m': expected a torque > 0"), std::string::npos) << r.err;
  r = run_poise(dir, "diagnose '" + kTable1 + "' --noise '0.2 deg'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--noise '0.2 deg'"), std::string::npos) << r.err;
  r = run_poise(dir, "diagnose '" + kTable1 + "' --alpha 1.5");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("expected 0 < alpha < 1"), std::string::npos) << r.err;
}

TEST(DiagnoseCommand, DiagnoseRecordTurnsEveryFailureIntoAnErrorWithFileAndLine) {
  poise::test::TempDir dir;
  std::string csv = "time_s,current_A,phi_deg\n";
  for (int k = 0; k < 300; ++k) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.6f,%.6f,%.6f\n", k * 1e-3 - (k == 121 ? 1e-3 : 0.0),
                  0.2 + 0.05 * std::sin(0.02 * k), 1.27 * std::sin(0.02 * k));
    csv += buf;
  }
  const std::string rec = dir.file("rec.csv");
  poise::test::write_text(rec, csv);
  RunResult r = run_poise(dir, "diagnose-record '" + rec + "'");
  EXPECT_EQ(r.status, 2);
  // Jittered stamps are used as they are; a stamp that repeats the one before is refused at its line.
  EXPECT_NE(r.err.find(rec + ":123: time 0.12 s repeats the stamp of the row before"), std::string::npos) << r.err;
  r = run_poise(dir, "diagnose-record '" + rec + "' --kt '1e308 N*m/A'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("the torque constant K_T"), std::string::npos) << r.err;
  r = run_poise(dir, "diagnose-record '" + rec + "' --kt '0.05 N*m'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--kt '0.05 N*m'"), std::string::npos) << r.err;
}

TEST(DiagnoseCommand, HelpExplainsTheMethodWithTheTable1Example) {
  poise::test::TempDir dir;
  const RunResult r = run_poise(dir, "diagnose --help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("Holm"), std::string::npos);
  EXPECT_NE(r.out.find("poise diagnose data/yang2015/table1_loading_test_36pt.csv"),
            std::string::npos);
}

}  // namespace

namespace {

TEST(DiagnoseCommand, NumericOptionsAtTheEdgesOfDoubleAreRefusedOrAnswered) {
  // Found probing the numeric options beside the fuzzed torque tables (issue 20): a known
  // load of 1e308 N*m gave "n/a" errors (infinities), and --noise "1e-300 mN*m" stopped
  // with a Boost.Math error (an infinite chi-square statistic) and exit 1.
  poise::test::TempDir dir;
  RunResult r = run_poise(dir, "diagnose '" + kTable1 + "' --load-torque '1e308 N*m' --load-angle '0 deg'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--load-torque '1e308 N*m': expected a torque >= 0 and at most 1e9 N*m"), std::string::npos)
      << r.err;
  r = run_poise(dir, "diagnose '" + kTable1 + "' --load-torque '12.91 mN*m' --load-angle '1e300 deg'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--load-angle '1e300 deg': expected an angle within +-3600 deg"), std::string::npos) << r.err;
  // A declared noise far below the residuals: the lack-of-fit test rejects it (p = 0), no error.
  r = run_poise(dir, "diagnose '" + kTable1 + "' --noise '1e-300 mN*m' --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("boost"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("against declared 1e-300"), std::string::npos) << r.out.substr(0, 2000);
}

}  // namespace

namespace {

// Round 3 (issue: time effects by family): a linear drift in time on a shuffled plan is
// reported as family time_drift, shape linear; the older "name" key stays; the help says so.
TEST(DiagnoseCommand, TimeEffectsAreReportedByFamilyWithTheirShape) {
  poise::test::TempDir dir;
  std::string csv = "theta_deg,torque_mNm,time_s\n";
  unsigned state = 12345;  // a fixed shuffle and noise (LCG): the same table every run
  const auto uniform = [&state] { return (state = state * 1103515245u + 12345u) / 4294967296.0; };
  std::vector<int> order(36);
  for (int k = 0; k < 36; ++k) order[k] = k;
  for (int k = 35; k > 0; --k) std::swap(order[k], order[static_cast<int>(uniform() * (k + 1))]);
  for (int k = 0; k < 36; ++k) {
    const double theta = 10.0 * order[k], t = 60.0 * k;
    const double noise = 0.2 * (uniform() + uniform() + uniform() - 1.5) * 2.0;
    const double m = 12.9 * std::sin(theta * std::numbers::pi / 180.0 + 0.8) + 3.4 + 1.5e-3 * t + noise;
    csv += std::to_string(theta) + "," + std::to_string(m) + "," + std::to_string(t) + "\n";
  }
  const std::string data = dir.file("drift.csv");
  poise::test::write_text(data, csv);
  RunResult r = run_poise(dir, "diagnose '" + data + "' --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j.at("effects").size(), 1u) << j.at("effects").dump();
  const auto& e = j.at("effects")[0];
  EXPECT_EQ(e.at("name"), "time_drift");
  EXPECT_EQ(e.at("family"), "time_drift");
  EXPECT_EQ(e.at("shape"), "linear");
  EXPECT_NE(j.at("answer").get<std::string>().find("time_drift (linear)"), std::string::npos)
      << j.at("answer");
  r = run_poise(dir, "diagnose --help");
  EXPECT_NE(r.out.find("effects[].shape"), std::string::npos);
  EXPECT_NE(r.out.find("shape not identifiable"), std::string::npos);
}

TEST(DiagnoseCommand, AStepsChangePointTimeHasNoStandardErrorAndTheReportSaysNotNan) {
  poise::test::TempDir dir;
  std::string csv = "theta_deg,torque_mNm,time_s\n";
  unsigned state = 777;  // fixed noise (LCG): the same table every run
  const auto uniform = [&state] { return (state = state * 1103515245u + 12345u) / 4294967296.0; };
  for (int k = 0; k < 36; ++k) {
    const double theta = 10.0 * k, t = 12.0 * k;
    const double noise = 0.1 * (uniform() + uniform() + uniform() - 1.5) * 2.0;
    const double m = 9.0 * std::sin(theta * std::numbers::pi / 180.0 + 0.3) + 2.0 + (k >= 21 ? 1.5 : 0.0) + noise;
    csv += std::to_string(theta) + "," + std::to_string(m) + "," + std::to_string(t) + "\n";
  }
  const std::string data = dir.file("step.csv"), out = dir.file("diag");
  poise::test::write_text(data, csv);
  RunResult r = run_poise(dir, "diagnose '" + data + "' --out '" + out + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(poise::test::read_text(out + "/diagnosis.json"));
  ASSERT_FALSE(j.at("effects").empty()) << r.out;
  const auto& params = j.at("effects")[0].at("params");
  ASSERT_TRUE(params.contains("at_time")) << params.dump();
  EXPECT_TRUE(params.at("at_time").at("se").is_null());  // a scanned change point: no SE
  const std::string html = poise::test::read_text(out + "/report.html");
  EXPECT_NE(html.find("&plusmn; n/a s"), std::string::npos);
  EXPECT_EQ(html.find("&plusmn; nan"), std::string::npos);
  EXPECT_NE(r.out.find("+- n/a s"), std::string::npos) << r.out;
}

}  // namespace
