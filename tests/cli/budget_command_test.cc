// End-to-end tests of `poise budget`: the Wang 2011 budget file (JSON keys, verdicts, the Monte
// Carlo beside it, text and report), and every bad-input message with file, line and key, exit 2.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "test_util.h"

namespace {

using poise::test::RunResult;
using poise::test::run_poise;
using poise::test::TempDir;

const std::string kWang = poise::test::source_path("studies/wang2011_budget.toml");
const std::string kModel = poise::test::source_path("models/seeker_two_axis_wang2011.toml");

int line_of(const std::string& text, const std::string& needle) {
  const auto pos = text.find(needle);
  EXPECT_NE(pos, std::string::npos) << needle;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(pos), '\n'));
}

const nlohmann::json* find_named(const nlohmann::json& list, const std::string& name) {
  for (const auto& it : list) {
    if (it["name"] == name) return &it;
  }
  return nullptr;
}

TEST(BudgetCommand, WangBudgetJsonHasTheDocumentedFieldsVerdictsAndMonteCarlo) {
  TempDir dir;
  const RunResult r = run_poise(dir, "budget '" + kWang + "' --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  for (const char* key : {"lines", "groups", "combined", "at_confidence", "requirement_met", "monte_carlo",
                          "budget_vs_monte_carlo", "unmapped_model_tolerances", "unknown_model_keys"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  const auto* s21 = find_named(j["lines"], "sigma_21 pitch axis perpendicularity");
  ASSERT_NE(s21, nullptr);
  EXPECT_EQ((*s21)["verdict"], "disagrees");
  EXPECT_NEAR((*s21)["recomputed"].get<double>(), 14.733, 1e-3);
  EXPECT_EQ((*s21)["declared"].get<double>(), 18.41);
  EXPECT_NEAR((*s21)["relative_difference"].get<double>(), 18.41 / 14.7332 - 1, 1e-4);
  EXPECT_TRUE(s21->contains("slip"));
  const auto* s11 = find_named(j["lines"], "sigma_11 yaw axis perpendicularity");
  EXPECT_EQ((*s11)["verdict"], "agrees");
  const auto* runout = find_named(j["lines"], "yaw radial run-out");
  EXPECT_EQ((*runout)["verdict"], "no_declared");
  EXPECT_TRUE(runout->contains("recomputed_min") && runout->contains("recomputed_max"));
  const auto* s12 = find_named(j["groups"], "sigma_12 yaw wobble");
  EXPECT_EQ((*s12)["verdict"], "agrees");
  EXPECT_EQ((*find_named(j["groups"], "delta_2 pitch shafting total"))["verdict"], "disagrees");
  EXPECT_NEAR(j["combined"]["least"].get<double>(), 10.47, 0.005);
  EXPECT_NEAR(j["combined"]["greatest"].get<double>(), 16.66, 0.005);
  EXPECT_EQ(j["combined"]["verdict_least"], "agrees");
  EXPECT_EQ(j["combined"]["verdict_greatest"], "disagrees");
  EXPECT_NEAR(j["at_confidence"]["multiple"].get<double>(), 1.0, 1e-3);
  EXPECT_EQ(j["requirement_met"], true);
  // The Monte Carlo of the exact chain at the same confidence: the budget is optimistic.
  const auto& mc = j["monte_carlo"];
  EXPECT_EQ(mc["output"], "los_max_arcsec");
  EXPECT_EQ(mc["quantile"].get<double>(), 0.6827);
  EXPECT_EQ(mc["samples"], 4000);
  EXPECT_LE(mc["ci95"][0].get<double>(), mc["value"].get<double>());
  EXPECT_GE(mc["ci95"][1].get<double>(), mc["value"].get<double>());
  EXPECT_GT(mc["ci95"][0].get<double>(), j["at_confidence"]["greatest"].get<double>());
  EXPECT_EQ(j["budget_vs_monte_carlo"], "optimistic");
  EXPECT_EQ(j["budget_vs_monte_carlo_decided"], true);
  // Every sampled tolerance of the model is covered (k' through the field).
  EXPECT_TRUE(j["unmapped_model_tolerances"].empty()) << j["unmapped_model_tolerances"].dump();
  EXPECT_TRUE(j["unknown_model_keys"].empty());
}

TEST(BudgetCommand, WangBudgetInWordsAndItsReport) {
  TempDir dir;
  const RunResult r = run_poise(dir, "budget '" + kWang + "' --out '" + dir.file("out") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("sigma_21 pitch axis perpendicularity"), std::string::npos);
  EXPECT_NE(r.out.find("DISAGREES"), std::string::npos);
  EXPECT_NE(r.out.find("likely slip: the declared value is 1.25 x the recomputed one"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("is optimistic against it"), std::string::npos);
  const std::string html = poise::test::read_text(dir.file("out/report.html"));
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("likely slip"), std::string::npos);
  EXPECT_NE(html.find("optimistic"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("src="), std::string::npos);  // self-contained
  const nlohmann::json j = nlohmann::json::parse(poise::test::read_text(dir.file("out/budget.json")));
  EXPECT_EQ(j["budget_vs_monte_carlo"], "optimistic");
  // One answer everywhere: the Monte Carlo decides (its quantile's lower 95% bound is past the
  // 1 px requirement) although the combination rule alone says met; the terminal ends with it
  // before the report's path, budget.json holds it and the report opens with it.
  EXPECT_EQ(j["requirement_met"], true);
  EXPECT_EQ(j["requirement_verdict"]["verdict"], "not met");
  const std::string answer = j["answer"].get<std::string>();
  EXPECT_EQ(answer.rfind("By the Monte Carlo of the model's exact chain: NOT met", 0), 0u) << answer;
  EXPECT_NE(answer.find("which the Monte Carlo contradicts"), std::string::npos) << answer;
  std::vector<std::string> lines;
  std::istringstream in(r.out);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) lines.push_back(line);
  }
  ASSERT_GE(lines.size(), 2u);
  EXPECT_EQ(lines[lines.size() - 2], answer);
  const auto at = html.find("class='answer'");
  ASSERT_NE(at, std::string::npos);
  EXPECT_LT(at, html.find("<h2"));
  EXPECT_EQ(html.find("The Monte Carlo does NOT meet"), std::string::npos);
}

TEST(BudgetCommand, UnmappedToleranceAndUnknownModelKeyAreListed) {
  TempDir dir;
  std::string text = poise::test::read_text(kWang);
  text = poise::test::replace_once(text, "model = \"../models/seeker_two_axis_wang2011.toml\"",
                                   "model = \"" + kModel + "\"");
  text = poise::test::replace_once(text, "samples = 4000", "samples = 200");
  text = poise::test::replace_once(text, "model_key = \"yaw.face_runout\"\n", "");
  text = poise::test::replace_once(text, "model_key = \"yaw.clearance\"", "model_key = \"yaw.clearence\"");
  poise::test::write_text(dir.file("b.toml"), text);
  const RunResult r = run_poise(dir, "budget '" + dir.file("b.toml") + "' --json");
  ASSERT_EQ(r.status, 0) << r.err;  // a warning, not an error
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const std::set<std::string> unmapped(j["unmapped_model_tolerances"].begin(), j["unmapped_model_tolerances"].end());
  EXPECT_EQ(unmapped, (std::set<std::string>{"yaw.face_runout", "yaw.clearance"}));
  ASSERT_EQ(j["unknown_model_keys"].size(), 1u);
  EXPECT_EQ(j["unknown_model_keys"][0]["key"], "yaw.clearence");
  const int line = line_of(text, "model_key = \"yaw.clearence\"");
  EXPECT_EQ(j["unknown_model_keys"][0]["line"], line);
  EXPECT_NE(r.err.find(dir.file("b.toml") + ":" + std::to_string(line) + ": key 'line[3].model_key' = \"yaw.clearence\""),
            std::string::npos)
      << r.err;
}

TEST(BudgetCommand, MonteCarloInTheBudgetsUnit) {
  // The same budget in urad: every figure, the Monte Carlo's included, converted (1 arcsec =
  // 4.8481 urad); same seed, same samples, so the same quantile.
  TempDir dir;
  std::string text = poise::test::read_text(kWang);
  text = poise::test::replace_once(text, "model = \"../models/seeker_two_axis_wang2011.toml\"",
                                   "model = \"" + kModel + "\"");
  text = poise::test::replace_once(text, "samples = 4000", "samples = 300");
  poise::test::write_text(dir.file("arcsec.toml"), text);
  poise::test::write_text(dir.file("urad.toml"), poise::test::replace_once(text, "unit = \"arcsec\"", "unit = \"urad\""));
  const RunResult a = run_poise(dir, "budget '" + dir.file("arcsec.toml") + "' --json");
  const RunResult u = run_poise(dir, "budget '" + dir.file("urad.toml") + "' --json");
  ASSERT_EQ(a.status, 0) << a.err;
  ASSERT_EQ(u.status, 0) << u.err;
  const nlohmann::json ja = nlohmann::json::parse(a.out), ju = nlohmann::json::parse(u.out);
  const double urad_per_arcsec = 1e6 / 206264.80624709636;
  EXPECT_NEAR(ju["monte_carlo"]["value"].get<double>(), ja["monte_carlo"]["value"].get<double>() * urad_per_arcsec, 1e-9);
  EXPECT_NEAR(ju["combined"]["greatest"].get<double>(), ja["combined"]["greatest"].get<double>() * urad_per_arcsec, 1e-9);
  EXPECT_EQ(ju["monte_carlo"]["unit"], "urad");
  EXPECT_EQ(ju["budget_vs_monte_carlo"], ja["budget_vs_monte_carlo"]);
  // Verdicts do not depend on the unit.
  for (std::size_t i = 0; i < ja["lines"].size(); ++i) EXPECT_EQ(ju["lines"][i]["verdict"], ja["lines"][i]["verdict"]);
}

// ---- bad input: file, line, key and what was expected; exit 2 ----

const std::string kBase = R"T([budget]
name = "t"
unit = "arcsec"
level = "1sigma"
combination = "rss"
confidence = 0.9973

[field]
pitch = ["-30 deg", "30 deg"]

[[line]]
name = "pitch axis perpendicularity"
tolerance = "0.003 mm"
lever = "48 mm"
distribution = "normal"
tolerance_is = "3sigma"
gain = "1/cos(pitch)"
declared = "4.30 arcsec"
)T";

struct BadCase {
  std::string name;
  std::string from, to;   // replaced in kBase ("" from: appended)
  std::string at;         // text whose line the message must name ("" = the line of `to`)
  std::string expected;   // part of the message after "file:line:col: "
};

class BudgetBadInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(BudgetBadInput, RefusedWithFileLineKeyAndExit2) {
  TempDir dir;
  const BadCase& c = GetParam();
  const std::string text = c.from.empty() ? kBase + c.to : poise::test::replace_once(kBase, c.from, c.to);
  const std::string path = dir.file("budget.toml");
  poise::test::write_text(path, text);
  const RunResult r = run_poise(dir, "budget '" + path + "'");
  EXPECT_EQ(r.status, 2) << r.out << r.err;
  const int line = line_of(text, c.at.empty() ? c.to : c.at);
  EXPECT_NE(r.err.find(path + ":" + std::to_string(line) + ":"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Nothing was checked."), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(
    Messages, BudgetBadInput,
    ::testing::Values(
        BadCase{"unknown_key", "level = \"1sigma\"", "level = \"1sigma\"\ncolour = \"red\"", "colour",
                "key 'budget.colour' = \"red\": expected no such key here (unknown key"},
        BadCase{"missing_unit", "tolerance = \"0.003 mm\"", "tolerance = 0.003", "",
                "key 'line[0].tolerance' = 0.003: expected a length with its unit in quotes, e.g. \"0.003 mm\" (missing unit)"},
        BadCase{"lever_without_tolerance", "tolerance = \"0.003 mm\"\n", "", "lever = ",
                "key 'line[0].lever': expected a tolerance to go with the lever"},
        BadCase{"gain_unknown_variable", "gain = \"1/cos(pitch)\"", "gain = \"1/cos(roll)\"", "",
                "key 'line[0].gain' = \"1/cos(roll)\": expected unknown variable 'roll' (the [field] defines: pitch)"},
        BadCase{"gain_does_not_parse", "gain = \"1/cos(pitch)\"", "gain = \"1/cos(pitch\"", "",
                "key 'line[0].gain' = \"1/cos(pitch\": expected an expression muParser can read"},
        BadCase{"gain_not_finite", "gain = \"1/cos(pitch)\"", "gain = \"1/pitch\"", "",
                "key 'line[0].gain' = \"1/pitch\": expected a finite value over the whole field (not finite at pitch = 0 deg)"},
        BadCase{"confidence_above_1", "confidence = 0.9973", "confidence = 1.5", "",
                "key 'budget.confidence' = 1.5: expected a probability between 0 and 1"},
        BadCase{"confidence_zero", "confidence = 0.9973", "confidence = 0", "",
                "key 'budget.confidence' = 0: expected a probability between 0 and 1"},
        BadCase{"unknown_unit", "unit = \"arcsec\"", "unit = \"furlong\"", "",
                "key 'budget.unit' = \"furlong\": expected a unit such as \"arcsec\""},
        BadCase{"lever_in_a_length_budget", "unit = \"arcsec\"", "unit = \"mm\"", "lever = ",
                "key 'line[0].lever' = \"48 mm\": expected no lever in a budget in mm"},
        BadCase{"declared_wrong_dimension", "declared = \"4.30 arcsec\"", "declared = \"4.30 mm\"", "",
                "key 'line[0].declared' = \"4.30 mm\": expected an angle with its unit"},
        BadCase{"value_with_tolerance", "gain = \"1/cos(pitch)\"", "value = \"2 arcsec\"", "distribution = ",
                "key 'line[0].distribution': expected no distribution in a line given as a value"},
        BadCase{"normal_with_bounds", "tolerance_is = \"3sigma\"", "tolerance_is = \"bounds\"", "distribution = ",
                "a normal distribution has no bounds"},
        BadCase{"fixed_random_line", "distribution = \"normal\"", "distribution = \"fixed\"", "",
                "expected kind = \"bias\" for a fixed value"},
        BadCase{"field_variable_reserved", "pitch = [\"-30 deg\", \"30 deg\"]", "sin = [\"-30 deg\", \"30 deg\"]", "",
                "key 'field.sin': expected a variable name"},
        BadCase{"field_range_mixed_units", "pitch = [\"-30 deg\", \"30 deg\"]", "pitch = [\"-30 deg\", \"30 mm\"]", "",
                "expected both ends in the same kind of unit"},
        BadCase{"requirement_in_px_without_pixel", "confidence = 0.9973", "confidence = 0.9973\nrequirement = \"1 px\"",
                "requirement", "key 'budget.requirement' = \"1 px\": expected an angle with its unit, e.g. \"4.3 arcsec\" (a pixel count given; [budget] pixel"},
        BadCase{"duplicate_name", "", "\n[[line]]\nname = \"pitch axis perpendicularity\"\nvalue = \"1 arcsec\"\n",
                "name = \"pitch axis perpendicularity\"\nvalue", "key 'line[1].name' = \"pitch axis perpendicularity\": expected a name no other"},
        BadCase{"unknown_member", "", "\n[[group]]\nname = \"g\"\nmembers = [\"pitch axis\"]\n", "members = ",
                "key 'group[0].members' = \"pitch axis\": expected the name of a [[line]] or [[group]]"},
        BadCase{"output_without_model", "confidence = 0.9973", "confidence = 0.9973\noutput = \"los_max_arcsec\"",
                "output", "key 'budget.output': expected a model to sample"},
        BadCase{"model_missing", "confidence = 0.9973", "confidence = 0.9973\nmodel = \"no_such_model.toml\"", "model = ",
                "key 'budget.model' = \"no_such_model.toml\": expected an existing model file"}),
    [](const auto& param_info) { return param_info.param.name; });

TEST(BudgetBadInput, NotABudgetFile) {
  TempDir dir;
  const std::string study = poise::test::source_path("studies/los_seeker_wang2011.toml");
  const RunResult r = run_poise(dir, "budget '" + study + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("1 error in the input:\n  " + study + ":1: key 'budget': expected a table [budget] (missing)"),
            std::string::npos)
      << r.err;
  const RunResult missing = run_poise(dir, "budget '" + dir.file("none.toml") + "'");
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("no such file"), std::string::npos) << missing.err;
}

TEST(BudgetBadInput, UnknownMonteCarloOutput) {
  TempDir dir;
  const std::string text =
      poise::test::replace_once(kBase, "confidence = 0.9973",
                                "confidence = 0.9973\nmodel = \"" + kModel + "\"\noutput = \"los_p95\"\nsamples = 100");
  poise::test::write_text(dir.file("b.toml"), text);
  const RunResult r = run_poise(dir, "budget '" + dir.file("b.toml") + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(dir.file("b.toml") + ":" + std::to_string(line_of(text, "output =")) +
                       ": key 'budget.output' = \"los_p95\": expected an output of the seeker_two_axis Monte Carlo: "
                       "los_max_arcsec, "),
            std::string::npos)
      << r.err;
}

TEST(BudgetBadInput, ModelOfAKindWithoutMonteCarlo) {
  TempDir dir;
  poise::test::write_text(dir.file("m.toml"), "[model]\nkind = \"spring_plate_machine\"\n");
  const std::string text = poise::test::replace_once(
      kBase, "confidence = 0.9973", "confidence = 0.9973\nmodel = \"m.toml\"\noutput = \"x\"");
  poise::test::write_text(dir.file("b.toml"), text);
  const RunResult r = run_poise(dir, "budget '" + dir.file("b.toml") + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("key 'budget.model' = \"m.toml\": expected a model file of a kind with a Monte Carlo "
                       "(seeker_two_axis); its [model] kind is \"spring_plate_machine\""),
            std::string::npos)
      << r.err;
}

TEST(BudgetBadInput, EveryProblemOfAFileAtOnce) {
  TempDir dir;
  std::string text = poise::test::replace_once(kBase, "confidence = 0.9973", "confidence = 2");
  text = poise::test::replace_once(text, "gain = \"1/cos(pitch)\"", "gain = \"1/cos(roll)\"");
  poise::test::write_text(dir.file("b.toml"), text);
  const RunResult r = run_poise(dir, "budget '" + dir.file("b.toml") + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("2 errors in the input"), std::string::npos) << r.err;
}

TEST(BudgetCommand, HelpTeachesTheFile) {
  TempDir dir;
  const RunResult r = run_poise(dir, "budget --help");
  EXPECT_EQ(r.status, 0);
  for (const char* s : {"tolerance_is", "bias_linear_random_rss", "model_key", "propagation", "agrees"}) {
    EXPECT_NE(r.out.find(s), std::string::npos) << s;
  }
}

}  // namespace
