// End-to-end tests of `poise fit`: runs the built executable on the paper's Table 1 and on
// bad files, checks the JSON keys and values, the text output and the exit status.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <set>
#include <algorithm>
#include <numbers>
#include <sstream>
#include <string>

#include "core/format.h"
#include "test_util.h"

namespace {

using poise::test::RunResult;
using poise::test::run_poise;

const std::string kTable1 =
    poise::test::source_path("data/yang2015/table1_loading_test_36pt.csv");

TEST(FitCommand, JsonForTable1HasExactlyTheDocumentedKeysAndTheFit) {
  poise::test::TempDir dir;
  const RunResult r = run_poise(dir, "fit '" + kTable1 + "' --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  std::set<std::string> keys;
  for (const auto& [key, value] : j.items()) keys.insert(key);
  EXPECT_EQ(keys,
            (std::set<std::string>{"amplitude", "phase_deg", "offset", "rmse", "max_abs_residual",
                                   "unit", "n_points", "standard_errors", "sigma", "residuals"}));
  EXPECT_EQ(j.at("unit"), "mN*m");
  EXPECT_EQ(j.at("n_points"), 36);
  // Least-squares fit of the printed table (the paper's Eq. 24 says 12.04, 44.20, 3.47; see
  // sine_fit_test.cc); max residual as the paper reports, 0.64 mN*m.
  EXPECT_NEAR(j.at("amplitude").get<double>(), 12.4747, 1e-4);
  EXPECT_NEAR(j.at("phase_deg").get<double>(), 42.4290, 1e-4);
  EXPECT_NEAR(j.at("offset").get<double>(), 3.428333, 1e-6);  // mean of the 36 values
  EXPECT_NEAR(j.at("max_abs_residual").get<double>(), 0.6364, 1e-4);
  EXPECT_NEAR(j.at("rmse").get<double>(), 0.22512, 1e-5);
  EXPECT_NEAR(j.at("sigma").get<double>(), 0.22512 * std::sqrt(36.0 / 33.0), 1e-5);
  const auto& se = j.at("standard_errors");
  EXPECT_EQ(se.size(), 3u);
  EXPECT_NEAR(se.at("amplitude").get<double>(), j.at("sigma").get<double>() / std::sqrt(18.0),
              1e-9);
  EXPECT_NEAR(se.at("offset").get<double>(), j.at("sigma").get<double>() / 6.0, 1e-9);
  EXPECT_NEAR(se.at("phase_deg").get<double>(), 0.2545, 1e-4);

  const auto& res = j.at("residuals");
  ASSERT_EQ(res.size(), 36u);
  double max_abs = 0.0;
  for (const auto& row : res) {
    EXPECT_EQ(row.size(), 4u);
    const double measured = row.at("measured"), fitted = row.at("fitted");
    EXPECT_NEAR(row.at("residual").get<double>(), measured - fitted, 1e-12);
    max_abs = std::max(max_abs, std::abs(row.at("residual").get<double>()));
  }
  EXPECT_DOUBLE_EQ(max_abs, j.at("max_abs_residual").get<double>());
  EXPECT_EQ(res[2].at("theta_deg"), 20.0);
  EXPECT_EQ(res[2].at("measured"), 13.85);                          // as written in the file
  EXPECT_NEAR(res[2].at("residual").get<double>(), -0.6364, 1e-4);  // the largest one
}

TEST(FitCommand, TextOutputShowsTheFitWithUnitsAndTheTable) {
  poise::test::TempDir dir;
  const RunResult r = run_poise(dir, "fit '" + kTable1 + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("M(theta) = 12.47 sin(theta + 42.43 deg) + 3.43 mN*m"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("amplitude MT_s = 12.475 +- 0.055 mN*m"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("max |residual| = 0.636 mN*m"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("20.00       13.850       14.486       -0.636"), std::string::npos) << r.out;
}

TEST(FitCommand, ReadsALabsTableAsItComesWithItsOwnColumnsAndUnits) {
  // Table 1 as another lab keeps it: a comment, semicolons and decimal commas, the angle in
  // radians and the torque in N*m under headers of its own. The fit is the same, in N*m.
  poise::test::TempDir dir;
  std::istringstream in(poise::test::read_text(kTable1));
  std::string line, text = "# turntable test, unit 3\nangle [rad];M (N*m)\n";
  std::getline(in, line);
  while (std::getline(in, line)) {
    double theta = 0, torque = 0;
    if (std::sscanf(line.c_str(), "%lf,%lf", &theta, &torque) != 2) continue;
    std::string row = fmt::format("{:.12g};{:.12g}\n", theta * std::numbers::pi / 180.0, torque * 1e-3);
    std::replace(row.begin(), row.end(), '.', ',');
    text += row;
  }
  const std::string path = dir.file("lab.csv");
  poise::test::write_text(path, text);
  RunResult r = run_poise(dir, "fit '" + path + "' --column angle='angle [rad]' --column torque='M (N*m)' --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j.at("amplitude").get<double>(), 12.4747e-3, 1e-7) << r.out;
  // A torque column without a unit it can read is refused with the option that gives it.
  poise::test::write_text(path, "angle_deg;M\n0;1\n90;2\n180;1\n270;0\n");
  r = run_poise(dir, "fit '" + path + "' --column angle=angle_deg --column torque=M");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("expected --unit torque=UNIT"), std::string::npos) << r.err;
}

TEST(FitCommand, BadCellGivesStatus2AndNamesLineAndColumn) {
  poise::test::TempDir dir;
  const std::string bad = dir.file("bad.csv");
  poise::test::write_text(
      bad, poise::test::replace_once(poise::test::read_text(kTable1), "15.77", "15,77"));
  RunResult r = run_poise(dir, "fit '" + bad + "' --json");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(r.err.find(bad + ":6: row '40.00,15,77' has 3 cells"), std::string::npos) << r.err;

  poise::test::write_text(
      bad, poise::test::replace_once(poise::test::read_text(kTable1), "15.77", "1S.77"));
  r = run_poise(dir, "fit '" + bad + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(bad + ":6: column 'torque_mNm': cell '1S.77' is not a finite number"),
            std::string::npos)
      << r.err;
}

TEST(FitCommand, MissingFileGivesStatus2) {
  poise::test::TempDir dir;
  const RunResult r = run_poise(dir, "fit '" + dir.file("missing.csv") + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("cannot open"), std::string::npos) << r.err;
}

TEST(FitCommand, HelpTeachesTheFormatWithTheTable1Example) {
  poise::test::TempDir dir;
  const RunResult r = run_poise(dir, "fit --help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("M(theta) = MT_s sin(theta + b) + MK"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("theta_deg,torque_mNm"), std::string::npos);
  EXPECT_NE(r.out.find("poise fit data/yang2015/table1_loading_test_36pt.csv"),
            std::string::npos);
}

}  // namespace
