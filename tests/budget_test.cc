// The budget library (src/budget): every combination rule against hand computation, the
// confidence multiple, the field grid, the conventions of a line's sigma, each verdict and each
// slip reason, and the Wang 2011 budget file against the built-in recomputation of the paper's
// budget (models/seeker_los_budget.h), which it replaces.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "budget/budget_check.h"
#include "budget/budget_evaluation.h"
#include "budget/budget_file.h"
#include "budget/field_grid.h"
#include "core/units.h"
#include "models/seeker_los_budget.h"
#include "studies/seeker_model.h"
#include "test_util.h"

namespace {

using namespace poise::budget;
using poise::units::kArcsecPerRad;

constexpr double kArcsec = 1.0 / kArcsecPerRad;

BudgetSpec load_text(const poise::test::TempDir& dir, const std::string& text) {
  const std::string path = dir.file("budget.toml");
  poise::test::write_text(path, text);
  return load_budget(path);
}

const ItemResult& line(const BudgetResult& r, const std::string& name) {
  for (const auto& l : r.lines) {
    if (l.name == name) return l;
  }
  for (const auto& g : r.groups) {
    if (g.name == name) return g;
  }
  throw std::runtime_error("no item " + name);
}

std::string head(const std::string& combination, const std::string& extra = "") {
  return "[budget]\nname = \"t\"\nunit = \"arcsec\"\nlevel = \"1sigma\"\ncombination = \"" + combination +
         "\"\nconfidence = 0.9973\n" + extra + "\n";
}

// Two random lines (3 and 4 arcsec) and a bias (2 arcsec), given as values.
const std::string kThreeValues = R"T(
[[line]]
name = "a"
value = "3 arcsec"
[[line]]
name = "b"
value = "4 arcsec"
[[line]]
name = "c"
kind = "bias"
value = "2 arcsec"
)T";

TEST(BudgetCombination, ConfidenceMultipleIsTheTwoSidedNormalQuantile) {
  // Independent of Boost: erf(m / sqrt 2) is the two-sided probability of +-m sigma.
  for (double p : {0.6827, 0.9, 0.95, 0.9973}) {
    const double m = confidence_multiple(p);
    EXPECT_NEAR(std::erf(m / std::sqrt(2.0)), p, 1e-12) << p;
  }
  EXPECT_NEAR(confidence_multiple(0.9973), 3.0, 1e-3);
  EXPECT_NEAR(confidence_multiple(0.95), 1.959964, 1e-6);
}

TEST(BudgetCombination, EveryRuleAgainstHandComputation) {
  poise::test::TempDir dir;
  const double m = confidence_multiple(0.9973);
  struct Case {
    std::string rule;
    double combined, at_confidence;
  };
  const Case cases[] = {
      {"rss", std::sqrt(9.0 + 16.0 + 4.0), std::sqrt(9 * m * m + 16 * m * m + 4.0)},
      {"linear", 9.0, 7.0 * m + 2.0},
      {"bias_linear_random_rss", 2.0 + 5.0, 2.0 + 5.0 * m},
  };
  for (const auto& c : cases) {
    const BudgetResult r = check_budget(load_text(dir, head(c.rule) + kThreeValues));
    EXPECT_NEAR(r.combined.greatest / kArcsec, c.combined, 1e-9) << c.rule;
    EXPECT_NEAR(r.combined.least / kArcsec, c.combined, 1e-9) << c.rule;
    EXPECT_NEAR(r.at_confidence.greatest / kArcsec, c.at_confidence, 1e-9) << c.rule;
    EXPECT_EQ(line(r, "a").verdict.verdict, "given");
  }
}

TEST(BudgetCombination, ALevelOf3SigmaIsNotScaledAt3Sigma) {
  poise::test::TempDir dir;
  std::string text = head("rss") + kThreeValues;
  text = poise::test::replace_once(text, "level = \"1sigma\"", "level = \"3sigma\"");
  const BudgetResult r = check_budget(load_text(dir, text));
  EXPECT_NEAR(r.random_scale, confidence_multiple(0.9973) / 3.0, 1e-12);
  EXPECT_NEAR(r.at_confidence.greatest, r.combined.greatest, 1e-4 * r.combined.greatest);
}

TEST(BudgetCombination, RequirementMetOrNotAtTheConfidence) {
  poise::test::TempDir dir;
  // rss at 3 sigma: sqrt((3m)^2 + (4m)^2 + 2^2) = 15.13 arcsec.
  const BudgetResult met = check_budget(load_text(dir, head("rss", "requirement = \"15.2 arcsec\"") + kThreeValues));
  ASSERT_TRUE(met.requirement_met.has_value());
  EXPECT_TRUE(*met.requirement_met);
  const BudgetResult not_met =
      check_budget(load_text(dir, head("rss", "requirement = \"15.0 arcsec\"") + kThreeValues));
  EXPECT_FALSE(*not_met.requirement_met);
}

TEST(BudgetField, AxisHasItsEndsAndZero) {
  const auto a = field_axis(-30, 30, 13);
  ASSERT_EQ(a.size(), 13u);
  EXPECT_EQ(a.front(), -30);
  EXPECT_EQ(a.back(), 30);
  EXPECT_EQ(a[6], 0.0);
  const auto b = field_axis(-10, 30, 4);  // -10, 3.33, 16.7, 30: zero inserted
  ASSERT_EQ(b.size(), 5u);
  EXPECT_EQ(b[1], 0.0);
  EXPECT_TRUE(std::is_sorted(b.begin(), b.end()));
  const auto c = field_axis(0.4, 0.96, 3);  // zero not in range
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0], 0.4);
  EXPECT_NEAR(c[1], 0.68, 1e-15);
  EXPECT_EQ(c[2], 0.96);
  EXPECT_EQ(field_axis(2, 2, 5), std::vector<double>{2});
}

TEST(BudgetField, GainRangeOverTheFieldOfANormalThreeSigmaTolerance) {
  poise::test::TempDir dir;
  const BudgetResult r = check_budget(load_text(dir, head("rss") + R"T(
[field]
pitch = ["-30 deg", "30 deg"]
[[line]]
name = "pitch axis perpendicularity"
tolerance = "0.003 mm"
lever = "48 mm"
distribution = "normal"
tolerance_is = "3sigma"
gain = "1/cos(pitch)"
declared = ["4.30 arcsec", "4.96 arcsec"]
)T"));
  const ItemResult& l = line(r, "pitch axis perpendicularity");
  const double base = 0.001e-3 / 48e-3 * kArcsecPerRad;  // sigma = 0.001 mm over 48 mm: 4.297 arcsec
  EXPECT_NEAR(l.recomputed.least / kArcsec, base, 1e-9);                                     // pitch = 0
  EXPECT_NEAR(l.recomputed.greatest / kArcsec, base / std::cos(30 * poise::units::kRadPerDeg), 1e-9);  // +-30 deg
  EXPECT_EQ(l.verdict.verdict, "agrees");
  EXPECT_EQ(l.verdict.compared, "least and greatest");
  EXPECT_EQ(r.grid_points, 13u);
}

TEST(BudgetLines, SigmaOfEachConventionAsInModelFiles) {
  poise::test::TempDir dir;
  const BudgetSpec spec = load_text(dir, head("rss") + R"T(
[[line]]
name = "u"
tolerance = "3 arcsec"
distribution = "uniform"
tolerance_is = "bounds"
[[line]]
name = "s"
tolerance = "3 arcsec"
distribution = "arcsine"
tolerance_is = "bounds"
[[line]]
name = "n2"
tolerance = "3 arcsec"
distribution = "normal"
tolerance_is = "2sigma"
[[line]]
name = "u3"
tolerance = "3 arcsec"
distribution = "uniform"
tolerance_is = "3sigma"
[[line]]
name = "f"
kind = "bias"
tolerance = "3 arcsec"
distribution = "fixed"
)T");
  const BudgetResult r = check_budget(spec);
  EXPECT_NEAR(line(r, "u").recomputed.greatest / kArcsec, 3 / std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(line(r, "s").recomputed.greatest / kArcsec, 3 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(line(r, "n2").recomputed.greatest / kArcsec, 1.5, 1e-12);
  EXPECT_NEAR(line(r, "u3").recomputed.greatest / kArcsec, 1.0, 1e-12);
  EXPECT_NEAR(line(r, "f").recomputed.greatest / kArcsec, 3.0, 1e-12);  // a fixed bias is its value
  EXPECT_EQ(line(r, "u").verdict.verdict, "no_declared");
}

// One line with a declared value; returns its result.
ItemResult one_line(const std::string& body, const std::string& extra = "") {
  poise::test::TempDir dir;
  const BudgetResult r = check_budget(load_text(dir, head("rss", extra) + body));
  return r.lines.front();
}

TEST(BudgetVerdicts, AgreesWithinOnePercentAndNotBeyond) {
  // sigma = 0.004 mm / 56 mm = 14.733 arcsec.
  const std::string body = R"T(
[[line]]
name = "p"
tolerance = "0.004 mm"
lever = "56 mm"
distribution = "normal"
tolerance_is = "1sigma"
declared = "DECL"
)T";
  const double rec = 0.004 / 56 * kArcsecPerRad;
  auto with = [&](double v) {
    return one_line(poise::test::replace_once(body, "DECL", std::to_string(v) + " arcsec"));
  };
  EXPECT_EQ(with(rec * 1.009).verdict.verdict, "agrees");
  EXPECT_EQ(with(rec * 0.991).verdict.verdict, "agrees");
  const ItemResult off = with(rec * 1.011);
  EXPECT_EQ(off.verdict.verdict, "disagrees");
  EXPECT_NEAR(*off.verdict.relative_difference, 0.011, 1e-6);
}

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

TEST(BudgetCombination, GroupsPropagationAndBiasesByHand) {
  poise::test::TempDir dir;
  // Random a (3) and b (4) in group g (rss, 5), entering with propagation 2 (10); bias c (2,
  // fixed) and random d (normal 3sigma of 6 arcsec: 2) at the top; bias_linear_random_rss:
  // combined = 2 + sqrt(10^2 + 2^2); at 0.9973 the random ones x m, the bias not.
  const BudgetResult r = check_budget(load_text(dir, head("bias_linear_random_rss") + R"T(
[[line]]
name = "a"
value = "3 arcsec"
[[line]]
name = "b"
tolerance = "4 arcsec"
distribution = "normal"
tolerance_is = "1sigma"
[[group]]
name = "g"
members = ["a", "b"]
combination = "rss"
propagation = "2"
declared = "5 arcsec"
[[line]]
name = "c"
kind = "bias"
tolerance = "2 arcsec"
distribution = "fixed"
[[line]]
name = "d"
tolerance = "6 arcsec"
distribution = "normal"
tolerance_is = "3sigma"
)T"));
  const double m = confidence_multiple(0.9973);
  EXPECT_EQ(line(r, "g").verdict.verdict, "agrees");  // the propagation is not part of its declared value
  EXPECT_NEAR(r.combined.greatest / kArcsec, 2.0 + std::sqrt(100.0 + 4.0), 1e-9);
  EXPECT_NEAR(r.at_confidence.greatest / kArcsec, 2.0 + m * std::sqrt(100.0 + 4.0), 1e-9);
  // A group of random lines is random; a group of biases would be a bias.
  EXPECT_FALSE(line(r, "g").bias);
}

TEST(BudgetVerdicts, OneDeclaredValueOverAFieldIsTheGreatest) {
  const ItemResult r = one_line(R"T(
[[line]]
name = "x"
tolerance = "2 arcsec"
distribution = "normal"
tolerance_is = "1sigma"
gain = "1/cos(pitch)"
declared = "2.3094 arcsec"
)T", "[field]\npitch = [\"-30 deg\", \"30 deg\"]\n");
  EXPECT_EQ(r.verdict.compared, "greatest");
  EXPECT_EQ(r.verdict.verdict, "agrees");
  EXPECT_TRUE(r.recomputed.varies());
  EXPECT_NEAR(r.recomputed.least / kArcsec, 2.0, 1e-12);
}

// ---- The Wang 2011 budget as a file, against the built-in recomputation it replaces ----

class WangBudget : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    spec_ = new BudgetSpec(load_budget(poise::test::source_path("studies/wang2011_budget.toml")));
    result_ = new BudgetResult(check_budget(*spec_));
    const auto model = poise::studies::load_seeker_model(poise::test::source_path("models/seeker_two_axis_wang2011.toml"));
    builtin_ = new poise::models::WangBudget(poise::models::compute_wang_budget(model.budget_inputs()));
  }
  static double term(const std::string& key) { return builtin_->term(key).value; }
  static inline BudgetSpec* spec_ = nullptr;
  static inline BudgetResult* result_ = nullptr;
  static inline poise::models::WangBudget* builtin_ = nullptr;
};

TEST_F(WangBudget, RecomputesWhatTheBuiltInBudgetRecomputes) {
  const BudgetResult& r = *result_;
  auto arcsec = [](double si) { return si / kArcsec; };
  EXPECT_NEAR(arcsec(line(r, "sigma_11 yaw axis perpendicularity").recomputed.greatest), term("sigma_11"), 1e-9);
  EXPECT_NEAR(arcsec(line(r, "sigma_12 yaw wobble").recomputed.least), term("sigma_12_min"), 1e-9);
  EXPECT_NEAR(arcsec(line(r, "sigma_12 yaw wobble").recomputed.greatest), term("sigma_12_max"), 1e-9);
  EXPECT_NEAR(arcsec(line(r, "sigma_13 yaw random wobble").recomputed.greatest), term("sigma_13"), 1e-9);
  EXPECT_NEAR(arcsec(line(r, "delta_1 yaw shafting total").recomputed.least), term("delta_1_min"), 1e-9);
  EXPECT_NEAR(arcsec(line(r, "delta_1 yaw shafting total").recomputed.greatest), term("delta_1_max"), 1e-9);
  EXPECT_NEAR(arcsec(line(r, "sigma_21 pitch axis perpendicularity").recomputed.greatest), term("sigma_21"), 1e-9);
  EXPECT_NEAR(arcsec(line(r, "sigma_22 pitch wobble").recomputed.least), term("sigma_22_min"), 1e-9);
  EXPECT_NEAR(arcsec(line(r, "sigma_23 pitch random wobble").recomputed.greatest), term("sigma_23"), 1e-9);
  EXPECT_NEAR(arcsec(line(r, "delta_2 pitch shafting total").recomputed.greatest), term("delta_2_max"), 1e-9);
  EXPECT_NEAR(arcsec(line(r, "delta_3 optical axis").recomputed.greatest), term("delta_3"), 1e-9);
  // The paper's Sec. 3 combination over the field (built-in: 61 x 61 points; here 13 per variable
  // with the ends and zero, where the extremes lie).
  EXPECT_NEAR(arcsec(r.combined.least), term("los_min"), 1e-9);
  EXPECT_NEAR(arcsec(r.combined.greatest), term("los_max"), 1e-9);
  // By hand: sigma_21 = 0.004 / 56 x 206264.8 arcsec.
  EXPECT_NEAR(term("sigma_21"), 0.004 / 56 * 206264.806, 1e-3);
}

TEST_F(WangBudget, VerdictsAreTheReportsVerdicts) {
  const BudgetResult& r = *result_;
  for (const auto& item : r.lines) {
    if (item.name == "sigma_21 pitch axis perpendicularity") continue;
    EXPECT_NE(item.verdict.verdict, "disagrees") << item.name;
  }
  for (const auto& item : r.groups) {
    if (item.name == "delta_2 pitch shafting total") continue;
    EXPECT_EQ(item.verdict.verdict, "agrees") << item.name;
  }
  const ItemResult& s21 = line(r, "sigma_21 pitch axis perpendicularity");
  EXPECT_EQ(s21.verdict.verdict, "disagrees");
  EXPECT_NE(s21.verdict.slip.find("1.25 x the recomputed one"), std::string::npos) << s21.verdict.slip;
  const ItemResult& d2 = line(r, "delta_2 pitch shafting total");
  EXPECT_EQ(d2.verdict.verdict, "disagrees");
  EXPECT_EQ(d2.verdict.verdict_least, "disagrees");
  EXPECT_EQ(d2.verdict.verdict_greatest, "disagrees");
  EXPECT_NE(d2.verdict.slip.find("\"sigma_21 pitch axis perpendicularity\""), std::string::npos);
  // los_min agrees, los_max disagrees; the printed range follows from the printed deltas.
  EXPECT_EQ(r.combined_verdict.verdict_least, "agrees");
  EXPECT_EQ(r.combined_verdict.verdict_greatest, "disagrees");
  EXPECT_NEAR(r.combined_from_declared->least / kArcsec, 10.47, 0.005);
  EXPECT_NEAR(r.combined_from_declared->greatest / kArcsec, 17.82, 0.005);
  EXPECT_NE(r.combined_verdict.slip.find("\"delta_2 pitch shafting total\""), std::string::npos);
  // los_min_px agrees, los_max_px disagrees.
  EXPECT_EQ(r.pixels_verdict.verdict_least, "agrees");
  EXPECT_EQ(r.pixels_verdict.verdict_greatest, "disagrees");
  // The paper's claim, at 1 sigma: the requirement (1 px) is met by the budget.
  EXPECT_TRUE(r.requirement_met.value());
}

}  // namespace
