// Tests of estimators/torque_table: the paper's Table 1, the accepted variations of the
// format, and every documented error with its message.
#include "estimators/torque_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "core/error.h"
#include "test_util.h"

namespace poise::estimators {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Writes text to a temporary file, expects read_torque_table to refuse it with a message
// containing "<file>" + suffix.
void expect_refused(const test::TempDir& dir, const std::string& text, const std::string& suffix) {
  const std::string path = dir.file("data.csv");
  test::write_text(path, text);
  try {
    read_torque_table(path);
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + suffix), std::string::npos)
        << "message: " << e.what() << "\nexpected to contain: " << path + suffix;
  }
}

const char* kGood = "theta_deg,torque_mNm\n0,1\n90,2\n180,3\n270,2\n";

TEST(TorqueTable, ReadsThePapersTable1) {
  const TorqueTable t =
      read_torque_table(test::source_path("data/yang2015/table1_loading_test_36pt.csv"));
  ASSERT_EQ(t.size(), 36u);
  EXPECT_EQ(t.torque_column, "torque_mNm");
  EXPECT_EQ(t.unit, "mN*m");
  EXPECT_EQ(t.unit_factor, 1e-3);
  EXPECT_EQ(t.theta_deg[1], 10.0);
  EXPECT_DOUBLE_EQ(t.theta_rad[35], 350.0 * kDeg);
  EXPECT_EQ(t.torque[0], 11.94);
  EXPECT_DOUBLE_EQ(t.torque_Nm[0], 11.94e-3);
  EXPECT_EQ(t.torque[35], 10.24);
  EXPECT_EQ(t.torque[17], -3.35);
  EXPECT_EQ(t.rows.front(), 2u);  // the header is line 1
  EXPECT_EQ(t.rows.back(), 37u);
  EXPECT_TRUE(t.time_s.empty());
  EXPECT_TRUE(t.sweep.empty());
}

TEST(TorqueTable, AcceptsBomCrlfSpacesBlankLinesNewtonsAndOptionalColumns) {
  test::TempDir dir;
  const std::string path = dir.file("data.csv");
  test::write_text(path,
                   "\xEF\xBB\xBF time_s , theta_deg ,note, torque_Nm ,sweep\r\n"
                   "0.5, 0 ,a, 0.011 ,+1\r\n"
                   "\r\n"
                   "1.5,120, b ,-2.5e-3,-1\r\n"
                   "2.5,+240,,0.004,1\r\n"
                   "3.5,360,c,0.012,-1.0\r\n");
  const TorqueTable t = read_torque_table(path);
  ASSERT_EQ(t.size(), 4u);
  EXPECT_EQ(t.torque_column, "torque_Nm");
  EXPECT_EQ(t.unit, "N*m");
  EXPECT_EQ(t.unit_factor, 1.0);
  EXPECT_EQ(t.torque_Nm[1], -2.5e-3);
  EXPECT_EQ(t.theta_deg[2], 240.0);
  EXPECT_EQ(t.rows, (std::vector<std::size_t>{2, 4, 5, 6}));  // blank line 3 skipped, counted
  EXPECT_EQ(t.time_s, (std::vector<double>{0.5, 1.5, 2.5, 3.5}));
  EXPECT_EQ(t.sweep, (std::vector<int>{1, -1, 1, -1}));
}

TEST(TorqueTable, RefusesAMissingFileAndAnEmptyOne) {
  test::TempDir dir;
  const std::string missing = dir.file("nope.csv");
  try {
    read_torque_table(missing);
    ADD_FAILURE() << "read a missing file";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), missing + ": cannot open the file for reading");
  }
  expect_refused(dir, "\n  \n", ": no header line; expected e.g. 'theta_deg,torque_mNm'");
}

TEST(TorqueTable, RefusesHeadersWithoutAngleOrWithNoneOrTwoTorqueColumns) {
  test::TempDir dir;
  expect_refused(dir, "angle,torque_mNm\n0,1\n90,2\n180,3\n270,4\n",
                 ":1: header 'angle,torque_mNm': no column 'theta_deg'");
  expect_refused(dir, "theta_deg,torque\n0,1\n90,2\n180,3\n270,4\n",
                 ":1: header 'theta_deg,torque': no torque column; expected 'torque_mNm' (mN*m) "
                 "or 'torque_Nm' (N*m)");
  expect_refused(dir, "theta_deg,torque_mNm,torque_Nm\n0,1,1\n90,2,2\n180,3,3\n270,4,4\n",
                 ":1: header 'theta_deg,torque_mNm,torque_Nm': two torque columns");
  expect_refused(dir, "theta_deg,torque_mNm,theta_deg\n0,1,1\n90,2,2\n180,3,3\n270,4,4\n",
                 ":1: header 'theta_deg,torque_mNm,theta_deg': column 'theta_deg' appears twice");
}

TEST(TorqueTable, RefusesBadCellsNamingLineColumnAndCell) {
  test::TempDir dir;
  expect_refused(dir, test::replace_once(kGood, "90,2", "90,abc"),
                 ":3: column 'torque_mNm': cell 'abc' is not a finite number");
  expect_refused(dir, test::replace_once(kGood, "180,3", "180 deg,3"),
                 ":4: column 'theta_deg': cell '180 deg' is not a finite number");
  expect_refused(dir, test::replace_once(kGood, "270,2", "270,nan"),
                 ":5: column 'torque_mNm': cell 'nan' is not a finite number");
  expect_refused(dir, test::replace_once(kGood, "90,2", " ,2"),
                 ":3: column 'theta_deg': empty cell; expected a number");
  expect_refused(dir, "theta_deg,torque_mNm,sweep\n0,1,1\n90,2,-1\n180,3,2\n270,4,1\n",
                 ":4: column 'sweep': cell '2'; expected +1 or -1");
}

TEST(TorqueTable, RefusesRaggedRows) {
  test::TempDir dir;
  expect_refused(
      dir, test::replace_once(kGood, "180,3", "180,3,7"),
      ":4: row '180,3,7' has 3 cells but the header has 2 columns 'theta_deg,torque_mNm'");
  expect_refused(dir, test::replace_once(kGood, "90,2", "90"),
                 ":3: row '90' has 1 cell but the header has 2 columns");
}

TEST(TorqueTable, RefusesFewerThanFourRowsAndDuplicateAnglesOnly) {
  test::TempDir dir;
  expect_refused(dir, "theta_deg,torque_mNm\n0,1\n90,2\n180,3\n",
                 ": 3 data rows; expected at least 4");
  expect_refused(dir, "theta_deg,torque_mNm\n0,1\n360,1.1\n90,2\n-270,2.1\n0,0.9\n",
                 ": duplicate angles only: 2 distinct value(s) of theta_deg modulo 360 deg in 5 "
                 "rows; expected at least 3");
}

}  // namespace
}  // namespace poise::estimators

namespace poise::estimators {
namespace {

TEST(TorqueTable, ReadsAStandardErrorColumnInEitherUnit) {
  test::TempDir dir;
  const std::string path = dir.file("se.csv");
  test::write_text(path, "theta_deg,torque_mNm,torque_se_Nm\n0,1,2e-4\n90,2,3e-4\n180,3,2e-4\n270,2,1e-4\n");
  const TorqueTable t = read_torque_table(path);
  ASSERT_EQ(t.torque_se.size(), 4u);
  EXPECT_NEAR(t.torque_se[1], 0.3, 1e-12);  // in the table's unit, mN*m
  expect_refused(dir, "theta_deg,torque_mNm,torque_se_mNm\n0,1,0.2\n90,2,0\n180,3,0.2\n270,2,0.1\n",
                 ":3: column 'torque_se_mNm': cell '0'; expected a standard error > 0");
  expect_refused(dir, "theta_deg,torque_mNm,torque_se_mNm,torque_se_Nm\n0,1,1,1\n",
                 ":1: header 'theta_deg,torque_mNm,torque_se_mNm,torque_se_Nm': two columns "
                 "'torque_se_mNm' and 'torque_se_Nm'; expected at most one");
}

}  // namespace
}  // namespace poise::estimators

namespace poise::estimators {
namespace {

TEST(TorqueTable, RefusesTorquesWhoseSquaresOverflowTheFits) {
  // Found by tests/fuzz (fuzz_torque_csv): a torque of 1e308 mN*m read as a finite number,
  // then `poise diagnose` stopped with a Boost.Math error (a NaN chi-square statistic) and
  // `poise fit` printed infinite standard errors. The bound is 1e9 N*m, in either unit.
  test::TempDir dir;
  const std::string table = "theta_deg,torque_mNm\n0,9.2\n90,12.9\n180,1e308\n270,-12.9\n";
  expect_refused(dir, table, ":4: column 'torque_mNm': cell '1e308'; expected a torque of at most 1e9 N*m");
  expect_refused(dir, "theta_deg,torque_Nm\n0,1\n90,-2e9\n180,3\n270,2\n",
                 ":3: column 'torque_Nm': cell '-2e9'; expected a torque of at most 1e9 N*m");
  expect_refused(dir, "theta_deg,torque_mNm,torque_se_Nm\n0,1,2e-4\n90,2,1e10\n180,3,2e-4\n270,2,1e-4\n",
                 ":3: column 'torque_se_Nm': cell '1e10'; expected a standard error > 0 and at most 1e9 N*m");
  // At the bound itself: read (1e12 mN*m = 1e9 N*m).
  const std::string path = dir.file("edge.csv");
  test::write_text(path, "theta_deg,torque_mNm\n0,1e12\n90,2\n180,-1e12\n270,2\n");
  EXPECT_EQ(read_torque_table(path).size(), 4u);
  // Through the commands: exit 2 with the file and line, no Boost message.
  test::write_text(dir.file("big.csv"), table);
  for (const char* command : {"diagnose", "fit"}) {
    const auto r = test::run_poise(dir, std::string(command) + " '" + dir.file("big.csv") + "'");
    EXPECT_EQ(r.status, 2) << command << ": " << r.err;
    EXPECT_NE(r.err.find(dir.file("big.csv") + ":4: column 'torque_mNm'"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("boost"), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace poise::estimators
