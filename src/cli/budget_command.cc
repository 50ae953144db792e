#include "cli/budget_command.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>

#include "budget/budget_check.h"
#include "budget/budget_file.h"
#include "budget/budget_json.h"
#include "budget/budget_monte_carlo.h"
#include "cli/budget_text.h"
#include "core/error.h"
#include "engine/kind_interface/output_spec.h"
#include "engine/report/budget_page.h"
#include "engine/results/requirements.h"
#include "engine/results/result_io.h"
#include "engine/study_files/toml_reader.h"
#include "sampling/statistics.h"

namespace poise::cli {
using budget::find_monte_carlo_kind;
using budget::model_kind_of;
using budget::monte_carlo_kinds;
using budget::MonteCarloKind;
using budget::MonteCarloValues;
namespace {

using nlohmann::json;

const char* kBudgetHelp = R"HELP(What it does:
  Reads an error budget as its author wrote it: lines with their tolerances, levers,
  distributions, gains and the contribution the author declared; recomputes every line from its
  inputs; says which declared values do not follow from them and the likely slip ("bounds read
  as sigma: the declared value is sqrt(3) x the recomputed one"); combines the lines by the
  stated rule at the requirement's confidence; and, when the budget names a model, sets the
  Monte Carlo of the model's exact chain beside it.

Budget file (TOML; every value with its unit):
  [budget]
  name = "seeker_los_budget"
  unit = "arcsec"              # of every contribution and of the combined figure
  level = "1sigma"             # what a contribution stands for: 1sigma | 2sigma | 3sigma
  combination = "rss"          # rss | linear | bias_linear_random_rss
  requirement = "25 arcsec"    # optional
  confidence = 0.9973          # the requirement's probability: random lines x 3.0 / level
  declared = ["10 arcsec", "18 arcsec"]   # optional: the author's combined figure
  pixel = "18.75 arcsec"       # optional IFOV: requirement = "1 px", declared_in_pixels = [...]
  field_points = 13            # optional: grid points per [field] variable
  model = "../models/seeker_two_axis_wang2011.toml"   # optional, with output, samples, seed
  output = "los_max_arcsec"
  samples = 4000
  seed = 7
  [field]                      # optional: variables of the gains, with their ranges
  pitch = ["-30 deg", "30 deg"]
  k = { range = [0.4, 0.96], model_key = "load_deformation" }   # a sampled model parameter
  [[line]]
  name = "pitch axis perpendicularity"
  kind = "random"              # random | bias
  tolerance = "0.003 mm"       # over the lever, an angle (no lever: already in the unit)
  lever = "48 mm"
  distribution = "normal"      # normal | uniform | arcsine | truncated_normal | fixed
  tolerance_is = "3sigma"      # bounds | 1sigma | 2sigma | 3sigma (as in model files)
  gain = "1/cos(pitch)"        # a number or an expression (muParser) of the field
  declared = "4.30 arcsec"     # or ["least", "greatest"] over the field
  model_key = "pitch.perpendicularity"
  [[line]]
  name = "boresight calibration residual"
  kind = "bias"
  value = "2 arcsec"           # given: nothing to recompute
  [[group]]                    # optional sub-totals the author wrote
  name = "pitch axis"
  members = ["pitch axis perpendicularity"]
  declared = "4.3 arcsec"
  propagation = "tan(pitch)"   # how an item enters the figure above it (lines too)

  A line's contribution: sigma of its tolerance / lever x gain x the level's sigmas; over a
  [field] the least and greatest over a grid with the ends and zero. Verdicts: "agrees"
  (within 1%), "disagrees", "given", "no_declared".

Example:
  poise budget studies/wang2011_budget.toml
  poise budget studies/wang2011_budget.toml --json --out /tmp/wang_budget

Output: the verdict of every line and group in words with the likely slip, the combined
figure, the Monte Carlo quantile at the confidence with its 95% interval, and whether the
budget is conservative or optimistic against it. --json: one object (lines, groups, combined,
at_confidence, requirement_met, monte_carlo, budget_vs_monte_carlo, unmapped_model_tolerances,
unknown_model_keys). --out DIR: report.html (self-contained) and budget.json.
Exit status: 0 success, 2 invalid input (file, line, key and what was expected), 1 other failure.
)HELP";

engine::ValidationError input_error(const std::string& file, int line, const std::string& key, const std::string& value,
                                    const std::string& expected) {
  return engine::ValidationError({InputError(SourceLocation{file, line, 0}, key, value, expected)});
}

// The Monte Carlo's kind and the model's tolerances, checked before anything is computed.
struct MonteCarloPlan {
  std::optional<MonteCarloKind> kind;
  std::string output_unit;
  std::vector<std::string> tolerance_keys;
};

MonteCarloPlan plan_monte_carlo(const budget::BudgetSpec& spec) {
  MonteCarloPlan plan;
  if (spec.model_path.empty()) return plan;
  const std::string model_kind = model_kind_of(spec.model_path);
  plan.kind = find_monte_carlo_kind(model_kind);
  if (!plan.kind) {
    std::string kinds;
    for (const auto& k : monte_carlo_kinds()) kinds += (kinds.empty() ? "" : ", ") + k.model_kind;
    throw input_error(
        spec.file, spec.model_line, "budget.model", engine::quote_value(spec.model_as_written),
        "a model file of a kind with a Monte Carlo (" + kinds + "); its [model] kind is \"" + model_kind + "\"");
  }
  std::string names;
  for (const auto& o : plan.kind->outputs(spec.model_path)) {
    names += (names.empty() ? "" : ", ") + o.name;
    if (o.name == spec.output) plan.output_unit = o.unit;
  }
  if (plan.output_unit.empty()) {
    throw input_error(spec.file, spec.output_line, "budget.output", engine::quote_value(spec.output),
                      "an output of the " + plan.kind->model_kind + " Monte Carlo: " + names);
  }
  units::Dimension dim{};
  try {
    dim = units::parse_quantity("1 " + plan.output_unit).dim;
  } catch (const Error&) {
    dim = units::kDimensionless;
  }
  if (!(dim == spec.dimension)) {
    throw input_error(spec.file, spec.output_line, "budget.output", engine::quote_value(spec.output),
                      "an output in the budget's kind of unit (" + spec.unit + "); this one is in " + plan.output_unit);
  }
  plan.tolerance_keys = plan.kind->tolerance_keys(spec.model_path);
  return plan;
}

// model_key checks: the model's tolerances no line covers, and the keys the model lacks
// (warnings: the budget is still checked).
void add_model_keys(const budget::BudgetSpec& spec, const MonteCarloPlan& plan, json& out) {
  json unmapped = json::array(), unknown = json::array();
  if (plan.kind) {
    const std::set<std::string> known(plan.tolerance_keys.begin(), plan.tolerance_keys.end());
    std::set<std::string> covered;
    auto check = [&](const std::string& key, const std::string& where, int line, const std::string& name) {
      if (key.empty()) return;
      covered.insert(key);
      if (!known.count(key)) {
        unknown.push_back({{"key", key}, {"in", where}, {"name", name}, {"line", line}});
        std::cerr << "poise: warning: " << spec.file << ":" << line << ": key '" << where << "' = \"" << key
                  << "\": the model has no such tolerance; it has: " <<
            [&] {
              std::string s;
              for (const auto& k : plan.tolerance_keys) s += (s.empty() ? "" : ", ") + k;
              return s;
            }() << '\n';
      }
    };
    for (const auto& l : spec.lines) check(l.model_key, l.path + ".model_key", l.model_key_line, l.name);
    for (const auto& v : spec.field) check(v.model_key, "field." + v.name + ".model_key", v.line, v.name);
    for (const auto& k : plan.tolerance_keys) {
      if (!covered.count(k)) unmapped.push_back(k);
    }
  }
  out["unmapped_model_tolerances"] = std::move(unmapped);
  out["unknown_model_keys"] = std::move(unknown);
}

// The Monte Carlo beside the budget: the output's quantile at the confidence, its 95% interval.
std::vector<double> add_monte_carlo(const budget::BudgetSpec& spec, const budget::BudgetResult& res,
                                    const MonteCarloPlan& plan, json& out, bool progress) {
  out["monte_carlo"] = nullptr;
  out["budget_vs_monte_carlo"] = nullptr;
  if (!plan.kind) return {};
  if (progress)
    std::cerr << "poise budget: Monte Carlo of " << spec.model_path << ", " << spec.samples << " samples (seed "
              << spec.seed << ")...\n";
  const MonteCarloValues mc = plan.kind->run(spec.model_path, spec.output, spec.samples, spec.seed);
  if (mc.values.empty()) throw Error("every Monte Carlo sample failed; nothing to compare the budget with");
  std::vector<double> v = mc.values;
  const double to_budget = units::unit_factor(plan.output_unit) / spec.unit_factor;
  for (double& x : v) x *= to_budget;
  std::sort(v.begin(), v.end());
  const sampling::Estimate q = sampling::quantile_sorted(v, spec.confidence);
  json ci = json::array({q.lo ? json(*q.lo) : json(nullptr), q.hi ? json(*q.hi) : json(nullptr)});
  out["monte_carlo"] = {{"model", spec.model_path},
                        {"kind", plan.kind->model_kind},
                        {"output", spec.output},
                        {"unit", spec.unit},
                        {"quantile", spec.confidence},
                        {"value", q.value},
                        {"ci95", ci},
                        {"samples", mc.samples},
                        {"failures", mc.failures},
                        {"seed", spec.seed},
                        {"method", "monte_carlo"},
                        {"wall_seconds", mc.wall_seconds}};
  const double budget_figure = res.at_confidence.greatest / spec.unit_factor;
  out["budget_vs_monte_carlo"] = budget_figure >= q.value ? "conservative" : "optimistic";
  out["budget_vs_monte_carlo_ratio"] = budget_figure / q.value;
  // Decided: the 95% interval of the quantile lies wholly on one side of the budget figure.
  out["budget_vs_monte_carlo_decided"] = (q.lo && *q.lo > budget_figure) || (q.hi && *q.hi < budget_figure);
  return v;
}

// The one answer to the budget's question, "is the requirement met at the confidence?": decided
// on the Monte Carlo of the exact chain (its quantile's one-sided 95% bound, the verdicts every
// study's requirements get), the combination rule's figure set beside it; by the rule alone
// only when no model is named. Adds "requirement_verdict" and "answer".
void add_budget_answer(const budget::BudgetSpec& spec, const std::vector<double>& mc_values, json& out) {
  out["requirement_verdict"] = nullptr;
  if (!spec.requirement) {
    out["answer"] = "No requirement is stated: the budget and the Monte Carlo are set side by side only.";
    return;
  }
  const json& a = out["at_confidence"];
  const double limit = *spec.requirement / spec.unit_factor;
  const double rule = a["greatest"].get<double>();  // in the budget's unit already
  const std::string rule_text = "the combination rule gives " + engine::format_significant(rule) + " " + spec.unit +
                                " at the confidence " + engine::format_significant(spec.confidence) + " and says " +
                                (rule <= limit ? "met" : "not met");
  if (mc_values.empty()) {
    out["answer"] = std::string(rule <= limit ? "Met" : "NOT met") +
                    " by the budget's combination rule alone (no model "
                    "to sample): " +
                    rule_text + " against " + spec.requirement_text + ".";
    return;
  }
  engine::Requirement r;
  r.output = spec.output;
  r.statistic = "p" + engine::format_significant(100.0 * spec.confidence, 6);
  r.at_most = true;
  r.limit_text = engine::format_significant(limit, 10) + (spec.unit.empty() ? "" : " " + spec.unit);
  r.confidence = 0.95;
  r.origin = spec.file;
  std::vector<std::size_t> index(mc_values.size());
  for (std::size_t i = 0; i < index.size(); ++i) index[i] = i;
  const std::vector<engine::OutputSpec> outputs = {{spec.output, spec.unit, ""}};
  const json verdicts = engine::judge_requirements({r}, outputs, [&](const std::string&) {
    return engine::OutputValues{.values = &mc_values, .ok_index = &index, .replicate_size = 0, .independent = true};
  });
  out["requirement_verdict"] = verdicts[0];
  std::string answer = engine::answer_sentence(verdicts, json::object(), outputs, "complete", mc_values.size());
  answer.pop_back();  // its period: the budget's clause follows
  const std::string verdict = verdicts[0]["verdict"].get<std::string>();
  const bool agree = (verdict == "met") == (rule <= limit) && verdict != "undecided";
  out["answer"] = "By the Monte Carlo of the model's exact chain: " + answer + "; " + rule_text +
                  (verdict == "undecided" ? ""
                   : agree                ? ", in agreement"
                                          : ", which the Monte Carlo contradicts") +
                  ".";
}

}  // namespace

json check_budget_file(const std::string& path, std::vector<double>* mc_values, bool progress) {
  const budget::BudgetSpec spec = budget::load_budget(path);
  const MonteCarloPlan plan = plan_monte_carlo(spec);
  const budget::BudgetResult res = budget::check_budget(spec);
  json j = budget::budget_json(spec, res);
  add_model_keys(spec, plan, j);
  std::vector<double> values = add_monte_carlo(spec, res, plan, j, progress);
  add_budget_answer(spec, values, j);
  if (mc_values) *mc_values = std::move(values);
  return j;
}

namespace {

int run_budget(const std::string& path, bool as_json, const std::string& out_dir) {
  try {
    std::vector<double> mc_values;
    const json j = check_budget_file(path, &mc_values);
    if (as_json) {
      std::cout << j.dump(2) << '\n';
    } else {
      print_budget_text(j, std::cout);
      std::cout << '\n' << j["answer"].get<std::string>() << '\n';  // the answer, last (before the report's path)
    }
    if (!out_dir.empty()) {
      std::filesystem::create_directories(out_dir);
      engine::write_file_atomic((std::filesystem::path(out_dir) / "budget.json").string(), j.dump(2) + "\n");
      engine::write_file_atomic((std::filesystem::path(out_dir) / "report.html").string(),
                                engine::budget_report_html(j, mc_values));
      if (!as_json) std::cout << "report: " << out_dir << "/report.html\n";
    }
  } catch (const engine::ValidationError& e) {
    std::cerr << "poise: " << e.what() << "\nNothing was checked.\n";
    return 2;
  } catch (const UsageError& e) {
    std::cerr << "poise: " << e.what() << "\nNothing was checked.\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "poise: error: " << e.what() << '\n';
    return 1;
  }
  return 0;
}

}  // namespace

BudgetHandler add_budget_command(CLI::App& app) {
  struct Options {
    std::string file, out;
    bool json = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub =
      app.add_subcommand("budget",
                         "check an error budget: every line recomputed from its inputs, verdicts and likely slips, the "
                         "combined figure at the requirement's confidence, the Monte Carlo of the model beside it");
  sub->add_option("BUDGET", opt->file, "budget file (TOML), e.g. studies/wang2011_budget.toml")->required();
  sub->add_flag("--json", opt->json, "print one JSON object instead of words");
  sub->add_option("--out,-o", opt->out, "folder for report.html (self-contained) and budget.json");
  sub->footer(kBudgetHelp);
  return [sub, opt]() -> std::optional<int> {
    if (!*sub) return std::nullopt;
    return run_budget(opt->file, opt->json, opt->out);
  };
}

}  // namespace poise::cli
