// Likely slips of a budget (src/budget/slip_detection.h): each reason a declared figure can
// disagree with its inputs, named when it reproduces the declared value.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "budget/budget_check.h"
#include "budget_test_util.h"

namespace {

using namespace poise::budget;
using poise::test::kArcsec;
using poise::units::kArcsecPerRad;

using poise::test::head;
using poise::test::line;
using poise::test::load_text;
using poise::test::one_line;

struct SlipCase {
  std::string name, body, extra, expected;
};

class BudgetSlips : public ::testing::TestWithParam<SlipCase> {};

TEST_P(BudgetSlips, NamesTheLikelySlip) {
  const ItemResult r = one_line(GetParam().body, GetParam().extra);
  EXPECT_EQ(r.verdict.verdict, "disagrees");
  EXPECT_NE(r.verdict.slip.find(GetParam().expected), std::string::npos) << r.verdict.slip;
}

std::string tol_line(const std::string& tol, const std::string& dist, const std::string& is, const std::string& declared,
                     const std::string& more = "") {
  return "[[line]]\nname = \"x\"\ntolerance = \"" + tol + "\"\ndistribution = \"" + dist + "\"\ntolerance_is = \"" +
         is + "\"\ndeclared = \"" + declared + "\"\n" + more;
}

INSTANTIATE_TEST_SUITE_P(
    Line, BudgetSlips,
    ::testing::Values(
        // uniform +-3: sigma 1.732; declared 3 = sqrt(3) x.
        SlipCase{"bounds_read_as_sigma", tol_line("3 arcsec", "uniform", "bounds", "3 arcsec"), "",
                 "bounds read as sigma: the declared value is sqrt(3) x the recomputed one"},
        SlipCase{"arcsine_bounds_read_as_sigma", tol_line("3 arcsec", "arcsine", "bounds", "3 arcsec"), "",
                 "bounds read as sigma: the declared value is sqrt(2) x"},
        SlipCase{"three_sigma_read_as_one", tol_line("3 arcsec", "normal", "3sigma", "3 arcsec"), "",
                 "a 3 sigma tolerance read as 1 sigma: the declared value is 3 x"},
        SlipCase{"level_mix_up", tol_line("3 arcsec", "normal", "1sigma", "6 arcsec"), "",
                 "level mix-up: the declared value is 2 x the recomputed one, a 2-sigma figure in a 1-sigma budget"},
        SlipCase{"degrees_radians", tol_line("1 arcsec", "normal", "1sigma", "57.2958 arcsec"), "",
                 "degrees/radians"},
        SlipCase{"arcsec_degrees", tol_line("1 arcsec", "normal", "1sigma", "3600 arcsec"), "", "(deg/arcsec)"},
        SlipCase{"gain_left_out", tol_line("2 arcsec", "normal", "1sigma", "2 arcsec", "gain = \"1/cos(pitch)\"\n"),
                 "[field]\npitch = [\"30 deg\", \"30 deg\"]\n", "the gain (1/cos(pitch)) left out"},
        // 1/cos(30 rad) = 6.4805: the angle in degrees fed to cos as radians.
        SlipCase{"gain_in_degrees",
                 tol_line("2 arcsec", "normal", "1sigma", "12.966 arcsec", "gain = \"1/cos(pitch)\"\n"),
                 "[field]\npitch = [\"30 deg\", \"30 deg\"]\n", "evaluated with the angles in degrees"},
        SlipCase{"gain_inverted", tol_line("2 arcsec", "normal", "1sigma", "1.7321 arcsec", "gain = \"1/cos(pitch)\"\n"),
                 "[field]\npitch = [\"30 deg\", \"30 deg\"]\n", "inverted"},
        // 0.004 mm over 56 mm printed as 18.41 arcsec (Wang 2011 sigma_21): no named slip, the lever
        // or tolerance that would give it.
        SlipCase{"lever_ratio",
                 "[[line]]\nname = \"x\"\ntolerance = \"0.004 mm\"\nlever = \"56 mm\"\ndistribution = \"normal\"\n"
                 "tolerance_is = \"1sigma\"\ndeclared = \"18.41 arcsec\"\n",
                 "", "a lever 0.8 x the stated one (44.8 mm instead of 56 mm), or a tolerance of 0.005 mm"}),
    [](const auto& param_info) { return param_info.param.name; });

TEST(BudgetSlips, TheLeverOfAnotherLine) {
  poise::test::TempDir dir;
  // Line "pitch" over 56 mm declared as if over 82 mm (10.06 arcsec instead of 14.73).
  const BudgetResult r = check_budget(load_text(dir, head("rss") + R"T(
[[line]]
name = "yaw"
tolerance = "0.004 mm"
lever = "82 mm"
distribution = "normal"
tolerance_is = "1sigma"
[[line]]
name = "pitch"
tolerance = "0.004 mm"
lever = "56 mm"
distribution = "normal"
tolerance_is = "1sigma"
declared = "10.06 arcsec"
)T"));
  EXPECT_EQ(line(r, "pitch").verdict.slip, "the lever of line \"yaw\" (82 mm) used instead of 56 mm");
}

std::string group_budget(const std::string& group_extra, const std::string& a_declared = "") {
  return head("rss") + "[[line]]\nname = \"a\"\ntolerance = \"3 arcsec\"\ndistribution = \"normal\"\n"
                       "tolerance_is = \"1sigma\"\n" + a_declared +
         "[[line]]\nname = \"b\"\ntolerance = \"4 arcsec\"\ndistribution = \"normal\"\ntolerance_is = \"1sigma\"\n"
         "[[group]]\nname = \"g\"\nmembers = [\"a\", \"b\"]\n" + group_extra;
}

TEST(BudgetSlips, GroupCombinedLinearlyInsteadOfRss) {
  poise::test::TempDir dir;
  const BudgetResult r = check_budget(load_text(dir, group_budget("declared = \"7 arcsec\"\n")));
  EXPECT_NEAR(line(r, "g").recomputed.greatest / kArcsec, 5.0, 1e-12);
  EXPECT_EQ(line(r, "g").verdict.slip, "combined by linear instead of rss");
}

TEST(BudgetSlips, GroupMemberLeftOut) {
  poise::test::TempDir dir;
  const BudgetResult r = check_budget(load_text(dir, group_budget("declared = \"4 arcsec\"\n")));
  EXPECT_EQ(line(r, "g").verdict.slip, "\"a\" left out");
}

TEST(BudgetSlips, GroupFollowsFromAWrongMember) {
  poise::test::TempDir dir;
  // a declared 6 (a level mix-up); the group's 7.211 = sqrt(36 + 16) follows from it.
  const BudgetResult r =
      check_budget(load_text(dir, group_budget("declared = \"7.211 arcsec\"\n", "declared = \"6 arcsec\"\n")));
  EXPECT_EQ(line(r, "a").verdict.verdict, "disagrees");
  EXPECT_EQ(line(r, "g").verdict.verdict, "disagrees");
  EXPECT_EQ(line(r, "g").verdict.slip,
            "it follows from the declared values of its entries: the difference comes from \"a\"");
  EXPECT_NEAR(line(r, "g").from_members_declared->greatest / kArcsec, std::sqrt(52.0), 1e-9);
}
}  // namespace
