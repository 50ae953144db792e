// Optimization over Monte Carlo studies (`poise optimize`): statistics, common random numbers,
// the bearing-span sizing of the LOS study (a monotone constraint with a known structure), the
// fresh-sample check deciding (exit status 3 and the nearest design that passes), a chance
// constraint that verifies, an infeasible requirement that ends with a clear message, strict files.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "optimize/optimization_study.h"
#include "engine/kind_interface/study_evaluation.h"
#include "engine/study_files/toml_reader.h"
#include "study_run_options.h"
#include "test_util.h"

namespace poise::optimize {
namespace {

using test::TempDir;

TEST(Statistic, QuantilesMomentsAndFractions) {
  const std::vector<double> v{5, 1, 4, 2, 3};
  EXPECT_DOUBLE_EQ(engine::statistic(v, "mean"), 3.0);
  EXPECT_DOUBLE_EQ(engine::statistic(v, "std"), std::sqrt(2.5));
  EXPECT_DOUBLE_EQ(engine::statistic(v, "min"), 1.0);
  EXPECT_DOUBLE_EQ(engine::statistic(v, "max"), 5.0);
  EXPECT_DOUBLE_EQ(engine::statistic(v, "p50"), 3.0);
  // Definition 8 (sampling/statistics.h): rank (n + 1/3) p + 1/3 = 5/3 for p25, 5.13 for
  // p90 (past n: the maximum).
  EXPECT_DOUBLE_EQ(engine::statistic(v, "p25"), 1.0 + 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(engine::statistic(v, "p90"), 5.0);
  EXPECT_DOUBLE_EQ(engine::statistic(v, "p99.73"), engine::statistic(v, "p99_73"));
  EXPECT_DOUBLE_EQ(engine::statistic(v, "fraction_le:2"), 0.4);
  EXPECT_DOUBLE_EQ(engine::statistic(v, "fraction_ge:4.5"), 0.2);
  EXPECT_THROW(engine::statistic(v, "p101"), Error);
  EXPECT_THROW(engine::statistic(v, "median"), Error);
  EXPECT_THROW(engine::statistic({}, "mean"), Error);
  EXPECT_TRUE(engine::is_statistic("p95"));
  EXPECT_FALSE(engine::is_statistic("fraction_le:x"));
}

// A small bearing-span sizing on the LOS study: 512 samples per evaluation.
std::string sizing_text(const std::string& at_most, const std::string& extra = "") {
  return R"([optimization]
name = "spans"
study = ")" + test::source_path("studies/los_seeker_wang2011.toml") + R"("
samples = 512
seed = 11
algorithm = "cobyla"
max_evaluations = 40
xtol_rel = 1e-4

[[variable]]
parameter = "yaw.bearing_span"
lower = "60 mm"
upper = "160 mm"
start = "140 mm"

[[variable]]
parameter = "pitch.bearing_span"
lower = "40 mm"
upper = "120 mm"
start = "100 mm"

[objective]
variable_sum = ["yaw.bearing_span", "pitch.bearing_span"]

[[constraint]]
output = "los_max_px"
statistic = "p95"
at_most = )" + at_most + extra + R"(

[verification]
samples = 1024
seed = 5
)";
}

TEST(OptimizationStudy, CommonRandomNumbersMakeTheObjectiveRepeatable) {
  TempDir d;
  test::write_text(d.file("opt.toml"), sizing_text("1.5"));
  const OptimizationSpec spec = load_optimization(d.file("opt.toml"));
  const std::map<std::string, std::string> design{{"yaw.bearing_span", "100 mm"}, {"pitch.bearing_span", "70 mm"}};
  const auto a = engine::evaluate_study(spec.base, design, spec.samples, spec.seed, 1);
  const auto b = engine::evaluate_study(spec.base, design, spec.samples, spec.seed, 2);
  const std::size_t k = a.index("los_max_px");
  EXPECT_EQ(a.values[k], b.values[k]);  // same numbers, any thread count
  // A slightly longer span moves every sample a little and the same way (CRN): the statistic
  // changes smoothly instead of by the sampling noise.
  auto longer = design;
  longer["yaw.bearing_span"] = "100.5 mm";
  const auto c = engine::evaluate_study(spec.base, longer, spec.samples, spec.seed, 1);
  const double p_a = engine::statistic(a.values[k], "p95"), p_c = engine::statistic(c.values[k], "p95");
  EXPECT_LT(p_c, p_a);
  EXPECT_LT(p_a - p_c, 0.01 * p_a);
  // A different seed gives a different sample (so the equality above is not trivial).
  const auto e = engine::evaluate_study(spec.base, design, spec.samples, spec.seed + 1, 1);
  EXPECT_NE(e.values[k], a.values[k]);
}

TEST(OptimizationStudy, BearingSpansShrinkUntilTheLosRequirementBinds) {
  TempDir d;
  test::write_text(d.file("opt.toml"), sizing_text("1.5"));
  // Through the command line: a point-value constraint puts the optimum on its limit, so its
  // fresh check straddles it: "design not verified", exit status 3, said everywhere.
  const auto r = test::run_poise(d, "optimize '" + d.file("opt.toml") + "' -q --no-plots --seed 11 --out '" + d.file("run") + "'");
  ASSERT_EQ(r.status, 3) << r.out << r.err;
  EXPECT_NE(r.out.find("DESIGN NOT VERIFIED"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("answer: "), std::string::npos) << r.out;
  const std::string dir = d.file("run");
  const auto summary = nlohmann::json::parse(test::read_text(dir + "/summary.json"));
  ASSERT_TRUE(summary["feasible"].get<bool>()) << summary.dump(2);
  EXPECT_FALSE(summary["verified"].get<bool>());
  EXPECT_EQ(summary["exit_status"].get<int>(), 3);
  EXPECT_EQ(summary["optimization"]["seed"].get<int>(), 11);
  const std::string answer = summary["answer"].get<std::string>();
  EXPECT_NE(answer.find("NOT verified"), std::string::npos) << answer;
  EXPECT_NE(answer.find("straddles the limit <= 1.5 px"), std::string::npos) << answer;
  EXPECT_NE(test::read_text(dir + "/report.html").find("Design NOT verified"), std::string::npos);
  const auto& run = summary["runs"][0];
  const double f = run["objective"].get<double>();
  std::printf("optimum %s, sum of spans %.3f mm after %d evaluations (%s)\n", run["x"].dump().c_str(), f,
              run["evaluations"].get<int>(), run["status"].get<std::string>().c_str());
  std::printf("answer: %s\n", answer.c_str());
  EXPECT_LT(f, 240.0 - 1.0);  // shorter than the start (140 + 100 mm)
  // At the optimum the requirement binds: p95 close to 1.5 px, not far below.
  const OptimizationSpec spec = load_optimization(d.file("opt.toml"));
  std::map<std::string, std::string> optimum = summary["optimum"].get<std::map<std::string, std::string>>();
  const auto at = engine::evaluate_study(spec.base, optimum, spec.samples, spec.seed, 2);
  const double p95 = engine::statistic(at.values[at.index("los_max_px")], "p95");
  EXPECT_LE(p95, 1.5 + 1e-6);
  EXPECT_GT(p95, 1.45);
  EXPECT_TRUE(summary["constraints_on_search_samples"][0]["binding"].get<bool>());
  // The fresh check with its interval, straddling the limit.
  const auto& check = summary["verification"]["constraints"][0];
  EXPECT_EQ(summary["verification"]["samples"].get<int>(), 1024);
  EXPECT_EQ(check["verdict"], "straddles the limit");
  EXPECT_LE(check["interval"]["value"].get<double>(), 1.5);
  EXPECT_GT(check["interval"]["hi"].get<double>(), 1.5);
  // The nearest design that passes: longer spans, passing on the check set and on other samples.
  const auto& nearest = summary["nearest_passing_design"];
  ASSERT_TRUE(nearest["found"].get<bool>()) << nearest.dump(2);
  EXPECT_EQ(nearest["recheck"]["verdict"], "passes");
  EXPECT_LE(nearest["recheck"]["constraints"][0]["interval"]["hi"].get<double>(), 1.5);
  EXPECT_GT(nearest["objective"].get<double>(), f);
  EXPECT_NE(answer.find("nearest design that passes"), std::string::npos) << answer;
  // history.csv names the constraint and keeps the failure share.
  const std::string history = test::read_text(dir + "/history.csv");
  EXPECT_NE(history.find("evaluation,yaw.bearing_span_mm,pitch.bearing_span_mm,objective_sum_mm,los_max_px.p95,"
                         "failure_share,feasible,message"),
            std::string::npos)
      << history.substr(0, 300);
}

// The same sizing with the constraint on the upper 95% bound of p95 (a chance constraint with
// confidence): longer spans than the point value's, and the fresh check passes.
TEST(OptimizationStudy, ChanceConstraintOptimumPassesItsFreshCheck) {
  TempDir d;
  test::write_text(d.file("opt.toml"),
                   test::replace_once(sizing_text("1.5", "\nbound = \"upper95\""), "xtol_rel = 1e-4", "xtol_rel = 1e-4\nreplicates = 2"));
  const OptimizationRun r = run_optimization(d.file("opt.toml"), test::quiet_run_options(d.file("run"), 2));
  EXPECT_EQ(r.exit_status, kExitVerified) << r.answer;
  const auto summary = nlohmann::json::parse(test::read_text(r.dir + "/summary.json"));
  EXPECT_TRUE(summary["verified"].get<bool>()) << summary["verification"].dump(2);
  EXPECT_EQ(summary["answer"].get<std::string>(), r.answer);
  EXPECT_NE(r.answer.find("verified"), std::string::npos) << r.answer;
  // What the answer cost is said with it: evaluations and full-model samples, the fresh
  // checks included (at least the search's evaluations and one fresh set).
  const std::size_t evaluations = summary["cost"]["design_evaluations"].get<std::size_t>();
  const std::size_t model_samples = summary["cost"]["model_samples"].get<std::size_t>();
  EXPECT_GE(model_samples, evaluations);
  EXPECT_GT(evaluations, 2u);
  EXPECT_NE(r.answer.find("it took " + std::to_string(evaluations) + " design evaluations (" +
                          std::to_string(model_samples) + " samples of the full model)"),
            std::string::npos)
      << r.answer;
  EXPECT_EQ(summary["verification"]["constraints"][0]["bound"], "upper95");
  EXPECT_LE(summary["verification"]["constraints"][0]["bound_value"].get<double>(), 1.5);
  // On the search's samples the bound binds, so the point value is below the limit.
  const auto& own = summary["constraints_on_search_samples"][0];
  EXPECT_TRUE(own["binding"].get<bool>());
  EXPECT_LT(own["interval"]["value"].get<double>(), 1.5);
  // Two searches with independent seeds: the spread of each span, and the answer rounded to it.
  const auto& spread = summary["optimum_spread"];
  EXPECT_EQ(spread["searches"].get<int>(), 2);
  for (const auto& v : spread["variables"]) {
    EXPECT_LE(v["min"].get<double>(), v["max"].get<double>());
    EXPECT_GE(v["supported_step"].get<double>(), 0.0);
  }
  EXPECT_NE(r.answer.find("over 2 searches"), std::string::npos) << r.answer;
  // The answer keeps the digits that tell designs apart: each span as summary.json's optimum
  // to 3 significant digits, never rounded to the spread's step (issue 52).
  for (const auto& [key, value] : summary["optimum"].items()) {
    const std::size_t at = r.answer.find(key + " ");
    ASSERT_NE(at, std::string::npos) << r.answer;
    const double said = std::stod(r.answer.substr(at + key.size() + 1));
    const double optimum = std::stod(value.get<std::string>());
    EXPECT_NEAR(said, optimum, 0.005 * std::abs(optimum)) << key << " in: " << r.answer;
  }
  std::printf("answer: %s\n", r.answer.c_str());
}

TEST(OptimizationStudy, InfeasibleRequirementEndsWithAClearMessage) {
  TempDir d;
  test::write_text(d.file("opt.toml"), test::replace_once(sizing_text("0.05"), "max_evaluations = 40", "max_evaluations = 12"));
  try {
    run_optimization(d.file("opt.toml"), test::quiet_run_options(d.file("run"), 2));
    FAIL() << "an infeasible requirement must not end with a silent best guess";
  } catch (const engine::ValidationError&) {
    FAIL() << "not an input error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("no design met the constraints"), std::string::npos) << m;
    EXPECT_NE(m.find("p95 of los_max_px <= 0.05"), std::string::npos) << m;
  }
  // The folder keeps what was tried.
  const std::string history = test::read_text(d.file("run") + "/history.csv");
  EXPECT_NE(history.find("evaluation,yaw.bearing_span_mm"), std::string::npos) << history;
  const auto summary = nlohmann::json::parse(test::read_text(d.file("run") + "/summary.json"));
  EXPECT_FALSE(summary["feasible"].get<bool>());
  // The command line says it too, with exit status 1.
  const auto r = test::run_poise(d, "optimize '" + d.file("opt.toml") + "' -q --no-plots --out '" + d.file("run2") + "'");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("no design met the constraints"), std::string::npos) << r.err;
}

TEST(OptimizationStudy, StrictFile) {
  TempDir d;
  auto error_of = [&](const std::string& text) {
    test::write_text(d.file("bad.toml"), text);
    try {
      load_optimization(d.file("bad.toml"));
    } catch (const engine::ValidationError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string base = sizing_text("1");
  std::string e = error_of(test::replace_once(base, "output = \"los_max_px\"", "output = \"los_max\""));
  EXPECT_NE(e.find("constraint[0].output"), std::string::npos) << e;
  EXPECT_NE(e.find("los_max_px"), std::string::npos) << e;  // lists the outputs
  e = error_of(test::replace_once(base, "lower = \"60 mm\"", "lower = \"170 mm\""));
  EXPECT_NE(e.find("upper > lower"), std::string::npos) << e;
  e = error_of(test::replace_once(base, "start = \"140 mm\"", "start = \"14 cm\""));
  EXPECT_NE(e.find("same unit"), std::string::npos) << e;
  e = error_of(test::replace_once(base, "statistic = \"p95\"", "statistic = \"median\""));
  EXPECT_NE(e.find("statistic"), std::string::npos) << e;
  e = error_of(test::replace_once(base, "algorithm = \"cobyla\"", "algorithm = \"newton\""));
  EXPECT_NE(e.find("algorithm"), std::string::npos) << e;
  e = error_of(test::replace_once(base, "parameter = \"yaw.bearing_span\"", "parameter = \"yaw.span\""));
  EXPECT_NE(e.find("objective.variable_sum"), std::string::npos) << e;  // no longer a variable
  e = error_of(test::replace_once(test::replace_once(base, "parameter = \"yaw.bearing_span\"", "parameter = \"yaw.span\""),
                                  "[\"yaw.bearing_span\",", "[\"yaw.span\","));
  EXPECT_NE(e.find("yaw.span"), std::string::npos) << e;  // not a key of the model
  e = error_of(sizing_text("1", "\nbound = \"lower95\""));
  EXPECT_NE(e.find("an upper bound (\"upper95\") with at_most"), std::string::npos) << e;
  e = error_of(sizing_text("1", "\nbound = \"upper\""));
  EXPECT_NE(e.find("constraint[0].bound"), std::string::npos) << e;
  e = error_of(test::replace_once(sizing_text("1", "\nbound = \"upper95\""), "statistic = \"p95\"", "statistic = \"max\""));
  EXPECT_NE(e.find("use a quantile"), std::string::npos) << e;
  e = error_of(base + "equivalence_margin = \"-5%\"\n");
  EXPECT_NE(e.find("equivalence_margin"), std::string::npos) << e;
  e = error_of(test::replace_once(base, "xtol_rel = 1e-4", "xtol_rel = 1e-4\nreplicate_size = 100"));
  EXPECT_NE(e.find("a power of two for a sobol design"), std::string::npos) << e;
  e = error_of(test::replace_once(base, "xtol_rel = 1e-4", "xtol_rel = 1e-4\nreplicate_size = 512"));
  EXPECT_NE(e.find("optimization.samples"), std::string::npos) << e;  // 512 samples: one replicate
  EXPECT_NE(e.find("at least 2 replicates"), std::string::npos) << e;
  e = error_of(test::replace_once(test::replace_once(base, "at_most = 1", "at_least = 1\nbound = \"upper95\""),
                                  "statistic = \"p95\"", "statistic = \"p5\""));
  EXPECT_NE(e.find("a lower bound (\"lower95\") with at_least"), std::string::npos) << e;
  e = error_of(test::replace_once(base, "at_most = 1", "at_most = 1\nat_least = 0"));
  EXPECT_NE(e.find("exactly one of at_least and at_most"), std::string::npos) << e;
}

TEST(OptimizationStudy, HelpDocumentsTheExitStatuses) {
  TempDir d;
  const auto r = test::run_poise(d, "optimize --help");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("3  design not verified"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("2  invalid input"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--seed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("bound = \"upper95\""), std::string::npos) << r.out;
}

TEST(OptimizationStudy, RepositoryOptimizationFilesLoad) {
  for (const char* f : {"studies/spring_plate_sizing.toml", "studies/bearing_span_sizing.toml",
                        "studies/bearing_span_sizing_housing.toml", "studies/test_plan_18_vs_36.toml",
                        "studies/test_plan_calibrated_rig.toml"}) {
    const OptimizationSpec s = load_optimization(test::source_path(f));
    EXPECT_FALSE(s.variables.empty()) << f;
    EXPECT_FALSE(s.constraints.empty()) << f;
  }
  // The sizing studies state their binding constraints with confidence.
  const OptimizationSpec spans = load_optimization(test::source_path("studies/bearing_span_sizing.toml"));
  EXPECT_EQ(to_string(spans.constraints[0].bound), "upper95");
  EXPECT_EQ(spans.base.replicate_size, 4096u);
  const OptimizationSpec plates = load_optimization(test::source_path("studies/spring_plate_sizing.toml"));
  EXPECT_EQ(to_string(plates.constraints[1].bound), "lower95");
}

// A tiny gimbal study (4 rigs, 8 positions, the reference load) as study.toml in `d`.
void write_tiny_gimbal_study(const TempDir& d) {
  test::write_text(d.file("study.toml"), R"([study]
name = "tiny"
kind = "gimbal_static_unbalance"
model = ")" + test::source_path("models/gimbal_simulator_yang2015.toml") + R"("
[sampling]
method = "monte_carlo"
samples = 4
seed = 3
[[group]]
name = "g"
positions = 8
[[group.load]]
mass = "25.81 g"
radius = "51.0 mm"
angle = "45.50 deg"
)");
}

// Two objectives on a tiny gimbal study: the unbalance error against the test time, with the
// number of positions a discrete choice. Checks the epsilon-constraint front (non-dominated,
// ordered, reaching both single-objective optima), the exact test times, and the comparison
// of the choices on fresh samples.
TEST(OptimizationStudy, ParetoFrontOfErrorAgainstTestTime) {
  TempDir d;
  write_tiny_gimbal_study(d);
  test::write_text(d.file("opt.toml"), R"([optimization]
name = "plan"
study = "study.toml"
samples = 4
seed = 5
algorithm = "cobyla"
max_evaluations = 5
[[variable]]
parameter = "oscillation.period"
lower = "1 s"
upper = "6 s"
start = "4 s"
[[choice]]
parameter = "group.positions"
values = ["8", "12"]
[overrides]
"oscillation.periods" = "1"
[objective]
output = "g_rmse_torque_mNm"
statistic = "p95"
[pareto]
output = "g_test_time_min"
statistic = "max"
points = 1
[verification]
samples = 8
seed = 9
)");
  const OptimizationSpec spec = load_optimization(d.file("opt.toml"));
  ASSERT_TRUE(spec.pareto.has_value());
  EXPECT_EQ(spec.overrides.at("oscillation.periods"), "1");
  const OptimizationOutcome out = optimize(spec, 2, false);
  ASSERT_TRUE(out.feasible);
  ASSERT_EQ(out.choices.size(), 2u);
  ASSERT_FALSE(out.front.empty());
  // Test time is exact: positions x (5 + 1 + 0.5 + T) s.
  double min_time = INFINITY, min_obj = INFINITY;
  for (const auto& p : out.pool) {
    const double n = std::stod(out.choices[p.choice].at("group.positions"));
    EXPECT_NEAR(p.second, n * (6.5 + p.x[0]) / 60.0, 1e-9);
    if (!p.feasible) continue;
    min_time = std::min(min_time, p.second);
    min_obj = std::min(min_obj, p.objective);
  }
  // The front: increasing time, decreasing error, nobody dominates it, both ends reached.
  for (std::size_t k = 1; k < out.front.size(); ++k) {
    EXPECT_GT(out.pool[out.front[k]].second, out.pool[out.front[k - 1]].second);
    EXPECT_LT(out.pool[out.front[k]].objective, out.pool[out.front[k - 1]].objective);
  }
  for (std::size_t f : out.front) {
    for (const auto& p : out.pool) {
      if (!p.feasible) continue;
      EXPECT_FALSE(p.second <= out.pool[f].second && p.objective < out.pool[f].objective &&
                   (p.second < out.pool[f].second || p.objective < out.pool[f].objective));
    }
  }
  EXPECT_DOUBLE_EQ(out.pool[out.front.front()].second, min_time);
  EXPECT_DOUBLE_EQ(out.pool[out.front.back()].objective, min_obj);
  // The shortest test: 8 positions at the shortest period.
  EXPECT_NEAR(min_time, 8 * 7.5 / 60.0, 1e-9);
  ASSERT_EQ(out.front_verification.size(), out.front.size());
  EXPECT_TRUE(out.front_verification[0]["objective"].contains("lo"));
  // Choices compared on the same fresh samples, also per parameter value.
  ASSERT_EQ(out.comparison["choices"].size(), 2u);
  const auto& by = out.comparison["by_parameter"][0];
  EXPECT_EQ(by["parameter"], "group.positions");
  ASSERT_EQ(by["values"].size(), 2u);
  int with_difference = 0;
  for (const auto& v : by["values"]) with_difference += v.contains("minus_best") ? 1 : 0;
  EXPECT_EQ(with_difference, 1);
  // The decision in words, choices by name, with the equivalence verdict.
  EXPECT_NE(out.answer.find("positions = "), std::string::npos) << out.answer;
  EXPECT_NE(out.answer.find("equivalen"), std::string::npos) << out.answer;
  EXPECT_EQ(out.answer.find("{"), std::string::npos) << out.answer;  // no raw JSON
  std::printf("answer: %s\n", out.answer.c_str());
  // The answer follows the intervals: a value cheaper in the second objective that meets its
  // constraints is passed over only when the headline is shown better than it (its paired
  // difference to the headline lies wholly above zero) and not equivalent to it.
  const auto& headline_row = out.comparison["choices"][out.best];
  ASSERT_TRUE(headline_row.contains("second"));
  for (const auto& v : by["values"]) {
    if (!v.contains("minus_best") || !v.contains("second") || v["constraints"] != "passes") continue;
    if (v["second"]["value"].get<double>() >= headline_row["second"]["value"].get<double>()) continue;
    ASSERT_TRUE(v["minus_best"].contains("lo")) << v.dump();
    EXPECT_GT(v["minus_best"]["lo"].get<double>(), 0.0) << v.dump();
    EXPECT_FALSE(v["equivalence"]["shown"].get<bool>()) << v.dump();
  }
  const bool no_difference = out.answer.rfind("No difference in p95 of g_rmse_torque_mNm between", 0) == 0;
  const bool equivalent = out.answer.find(" are equivalent within 5% ") != std::string::npos;
  const bool better = out.answer.find(" is better than ") != std::string::npos;
  const bool kept = out.answer.find(" is kept although ") != std::string::npos;
  EXPECT_TRUE(no_difference || equivalent || better || kept) << out.answer;
  // Another draw (search and fresh seeds) does not flip a headline the intervals do not
  // support: where neither answer shows one value better, both name the cheaper value.
  OptimizationSpec other = spec;
  other.seed = 77;
  other.verification_seed = 78;
  const OptimizationOutcome again = optimize(other, 2, false);
  ASSERT_TRUE(again.feasible);
  const auto undecided = [](const std::string& a) {
    return a.find(" is better than ") == std::string::npos && a.find(" is kept although ") == std::string::npos;
  };
  if (undecided(out.answer) && undecided(again.answer)) {
    EXPECT_EQ(out.choices[out.best].at("group.positions"), again.choices[again.best].at("group.positions"))
        << out.answer << "\n" << again.answer;
  }
}

// search_model = "fast": the searches and the selection set run the kind's fast model, the
// comparison set runs the full model on the finalists only (the selection pick and each
// choice value's best), the answer states the fast model's gap to the full one on the
// headline's fresh samples, and the cost is counted per model. A kind without a fast model
// refuses the key.
TEST(OptimizationStudy, FastSearchIsVerifiedOnTheFullModel) {
  TempDir d;
  write_tiny_gimbal_study(d);
  const std::string opt = R"([optimization]
name = "plan"
study = "study.toml"
samples = 4
seed = 5
algorithm = "cobyla"
max_evaluations = 4
search_model = "fast"
[[variable]]
parameter = "oscillation.period"
lower = "1 s"
upper = "6 s"
start = "4 s"
[[choice]]
parameter = "group.positions"
values = ["8", "12", "16"]
[[choice]]
parameter = "group.placement"
values = ["sequential", "back_and_forth"]
[overrides]
"oscillation.periods" = "1"
[objective]
output = "g_rmse_torque_mNm"
statistic = "p95"
[verification]
samples = 8
seed = 9
)";
  test::write_text(d.file("opt.toml"), opt);
  const OptimizationSpec spec = load_optimization(d.file("opt.toml"));
  ASSERT_TRUE(spec.fast_search);
  EXPECT_NE(spec.fast_model_text.find("whole periods"), std::string::npos) << spec.fast_model_text;
  const OptimizationOutcome out = optimize(spec, 2, false);
  ASSERT_TRUE(out.feasible);
  ASSERT_EQ(out.choices.size(), 6u);
  // Finalists: the pick, the best of each of 3 + 2 values: at most 5 of the 6, at least 3.
  std::size_t compared = 0;
  for (const auto& row : out.comparison["choices"]) {
    const bool c = row.value("compared", false);
    compared += c ? 1 : 0;
    EXPECT_EQ(row.contains("comparison"), c) << row.dump();
    if (row["best"].get<bool>()) {
      EXPECT_TRUE(c);
    }
  }
  EXPECT_GE(compared, 3u);
  EXPECT_LE(compared, 5u);
  for (const auto& p : out.comparison["by_parameter"]) {
    for (const auto& v : p["values"]) EXPECT_TRUE(out.comparison["choices"][v["run"].get<std::size_t>()]["compared"].get<bool>());
  }
  // The full model ran exactly the comparison set of the finalists; the fast model the rest.
  EXPECT_EQ(out.model_samples, compared * spec.verification_samples);
  EXPECT_EQ(out.design_evaluations - out.fast_evaluations, compared);
  EXPECT_GT(out.fast_samples, 6u * spec.verification_samples);
  // The headline's check is the full model's; the fast model on the same samples is close.
  EXPECT_EQ(out.check.samples, spec.verification_samples);
  ASSERT_TRUE(out.fast_model.contains("objective"));
  const double rel = out.fast_model["objective"]["relative"].get<double>();
  std::printf("fast model on the headline's fresh samples: relative difference %.2e\n", rel);
  EXPECT_LT(std::fabs(rel), 0.01);
  EXPECT_NE(out.answer.find("the searches ran the fast model"), std::string::npos) << out.answer;
  // A kind without a fast model: refused, naming the key.
  test::write_text(d.file("seeker_opt.toml"),
                   "[optimization]\nname = \"s\"\nstudy = \"" + test::source_path("studies/los_seeker_wang2011.toml") +
                       "\"\nsamples = 64\nseed = 1\nalgorithm = \"cobyla\"\nmax_evaluations = 2\nsearch_model = "
                       "\"fast\"\n[[variable]]\nparameter = \"yaw.bearing_span\"\nlower = \"60 mm\"\nupper = \"220 "
                       "mm\"\nstart = \"160 mm\"\n[objective]\nvariable_sum = [\"yaw.bearing_span\"]\n");
  try {
    load_optimization(d.file("seeker_opt.toml"));
    FAIL() << "a kind without a fast model accepted search_model = \"fast\"";
  } catch (const engine::ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("optimization.search_model"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("has no fast model"), std::string::npos) << e.what();
  }
}

TEST(OptimizationStudy, BootstrapIntervalCoversTheStatistic) {
  std::vector<double> v;
  for (int i = 0; i < 200; ++i) v.push_back(std::sin(0.37 * i) + 0.01 * i);
  const auto j = statistic_with_ci(v, "p95", 1);
  EXPECT_LE(j["lo"].get<double>(), j["value"].get<double>());
  EXPECT_GE(j["hi"].get<double>(), j["value"].get<double>());
  EXPECT_EQ(j, statistic_with_ci(v, "p95", 1));  // deterministic in the seed
  EXPECT_LT(j["hi"].get<double>() - j["lo"].get<double>(), 0.5);
}

}  // namespace
}  // namespace poise::optimize
