// The budget library (src/budget): every combination rule against hand computation, the
// confidence multiple, the field grid, the conventions of a line's sigma, the verdicts, and the
// Wang 2011 budget file against the built-in recomputation of the paper's budget
// (models/seeker_los_budget.h), which it replaces. Slip reasons: budget_slip_detection_test.cc.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "budget/budget_check.h"
#include "budget/budget_evaluation.h"
#include "budget/budget_file.h"
#include "budget/field_grid.h"
#include "budget_test_util.h"
#include "core/units.h"
#include "models/seeker_los_budget.h"
#include "model_files/seeker_model.h"

using namespace poise::model_files;  // the kinds' and model files' own namespaces

namespace {

using namespace poise::budget;
using poise::test::kArcsec;
using poise::units::kArcsecPerRad;

using poise::test::head;
using poise::test::line;
using poise::test::load_text;
using poise::test::one_line;


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
    const auto model = poise::model_files::load_seeker_model(poise::test::source_path("models/seeker_two_axis_wang2011.toml"));
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
