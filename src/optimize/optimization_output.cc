#include "optimize/optimization_output.h"
#include "core/diagnostics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "core/version.h"
#include "engine/kind_interface/procedure_study.h"
#include "engine/report/optimization_page.h"
#include "engine/results/provenance.h"
#include "engine/results/result_io.h"
#include "optimize/optimization_plots.h"
#include "sampling/distributed.h"

namespace poise::optimize {
namespace {
namespace fs = std::filesystem;
using engine::html_escape;
using nlohmann::json;

void write_history(const OptimizationSpec& spec, const OptimizationOutcome& out, const std::string& dir) {
  std::ostringstream h;
  for (const auto& c : spec.choices) h << engine::csv_text(c.parameter) << ',';
  h << "evaluation";
  for (const auto& v : spec.variables) h << ',' << v.parameter << (v.unit.empty() ? "" : "_" + v.unit);
  h << ',' << objective_name(spec);
  for (const auto& c : spec.constraints) h << ',' << engine::csv_text(c.name);
  h << ",failure_share,feasible,message\n";
  for (const auto& run : out.runs) {
    for (const auto& e : run.result.history) {
      for (const auto& c : spec.choices) h << engine::csv_text(run.choice.at(c.parameter)) << ',';
      h << e.evaluation;
      for (double x : e.x) h << ',' << engine::csv_number(x);
      h << ',' << engine::csv_number(e.result.objective);
      for (std::size_t k = 0; k < spec.constraints.size(); ++k) {
        h << ','
          << (k < e.result.constraints.size()
                  ? engine::csv_number(constraint_figure(spec.constraints[k], e.result.constraints[k]))
                  : "");
      }
      const auto it = run.designs.find(e.x);
      h << ',' << (it != run.designs.end() ? engine::csv_number(it->second.failure_share) : "") << ','
        << (e.feasible ? 1 : 0) << ',' << engine::csv_text(e.result.message) << '\n';
    }
  }
  engine::write_file_atomic((fs::path(dir) / "history.csv").string(), h.str());
}

void write_pareto_csv(const OptimizationSpec& spec, const OptimizationOutcome& out, const std::string& dir) {
  std::ostringstream p;
  for (const auto& c : spec.choices) p << engine::csv_text(c.parameter) << ',';
  p << "search";
  for (const auto& v : spec.variables) p << ',' << v.parameter << (v.unit.empty() ? "" : "_" + v.unit);
  p << ',' << objective_name(spec) << ",second." << spec.pareto->output << ",feasible,on_front\n";
  for (std::size_t i = 0; i < out.pool.size(); ++i) {
    const ParetoPoint& q = out.pool[i];
    for (const auto& c : spec.choices) p << engine::csv_text(out.choices[q.choice].at(c.parameter)) << ',';
    p << engine::csv_text(q.search);
    for (double x : q.x) p << ',' << engine::csv_number(x);
    p << ',' << engine::csv_number(q.objective) << ',' << engine::csv_number(q.second) << ',' << (q.feasible ? 1 : 0)
      << ',' << (std::find(out.front.begin(), out.front.end(), i) != out.front.end() ? 1 : 0) << '\n';
  }
  engine::write_file_atomic((fs::path(dir) / "pareto.csv").string(), p.str());
}

std::string design_cells(const OptimizationSpec& spec, const std::vector<double>& x) {
  std::string s;
  for (std::size_t i = 0; i < spec.variables.size() && i < x.size(); ++i) {
    const std::string& unit = spec.variables[i].unit;
    s += (s.empty() ? "" : ", ") + spec.variables[i].parameter + " = " + engine::format_significant(x[i], 4) +
         (unit.empty() ? "" : " " + unit);
  }
  return s;
}

json optimization_json(const OptimizationSpec& spec) {
  return {{"name", spec.name},
          {"title", spec.title},
          {"file", spec.file},
          {"study", spec.base.file},
          {"algorithm", to_string(spec.algorithm)},
          {"algorithm_advice", algorithm_advice(spec.algorithm)},
          {"samples_per_evaluation", spec.samples},
          {"seed", spec.seed},
          {"replicate_size", spec.base.replicate_size},
          {"max_failure_share", spec.max_failure_share()},
          {"common_random_numbers", true},
          {"max_evaluations", spec.max_evaluations},
          {"replicates", spec.replicates},
          {"verification_samples", spec.verification_samples},
          {"selection_seed", spec.selection_seed()},
          {"verification_seed", spec.verification_seed},
          {"recheck_seed", spec.recheck_seed()},
          {"search_model", spec.fast_search ? "fast" : "full"},
          {"equivalence_margin", spec.equivalence_margin_text},
          {"notes", spec.notes}};
}

json runs_json(const OptimizationSpec& spec, const OptimizationOutcome& out) {
  json runs = json::array();
  for (std::size_t r = 0; r < out.runs.size(); ++r) {
    const auto& run = out.runs[r];
    json x;
    for (std::size_t i = 0; i < spec.variables.size() && i < run.result.x.size(); ++i) {
      x[spec.variables[i].parameter] = value_text(run.result.x[i], spec.variables[i].unit);
    }
    runs.push_back({{"choice", run.choice},
                    {"label", choice_label(run.choice)},
                    {"status", run.result.status},
                    {"evaluations", run.result.evaluations},
                    {"feasible", run.result.feasible},
                    {"x", x},
                    {"design", design_cells(spec, run.result.x)},
                    {"objective", run.result.feasible ? json(run.result.best.objective) : json(nullptr)},
                    {"headline", out.feasible && r == out.best},
                    {"optimization_pick", out.feasible && r == out.optimization_pick}});
  }
  return runs;
}

/// summary.json: the answer, the verdict, the optimization as run, every search and, when a
/// design is feasible, its fresh-sample check, spread, comparison of choices and front.
json optimization_summary(const OptimizationSpec& spec, const OptimizationOutcome& out, int exit_status, int threads,
                          const std::string& started) {
  json s;
  s["answer"] = out.answer;
  s["cost"] = {{"design_evaluations", out.design_evaluations},
               {"model_samples", out.model_samples},
               {"fast_model_evaluations", out.fast_evaluations},
               {"fast_model_samples", out.fast_samples},
               {"search_model", spec.fast_search ? "fast" : "full"},
               {"what",
                "base-study runs (searches, replicates, fresh sets and checks; fast_model_evaluations of "
                "them on the kind's fast model) and the samples they simulated (model_samples of the "
                "full model, fast_model_samples of the fast one)"}};
  if (!out.fast_model.is_null()) s["fast_model"] = out.fast_model;
  s["verified"] = out.feasible && out.verified;
  s["exit_status"] = exit_status;
  s["optimization"] = optimization_json(spec);
  json constraints = json::array();
  for (const auto& c : spec.constraints) {
    constraints.push_back({{"name", c.name},
                           {"output", c.output},
                           {"statistic", c.statistic},
                           {"bound", to_string(c.bound)},
                           {"limit", c.limit()},
                           {"at_least", c.at_least.has_value()},
                           {"text", c.describe()}});
  }
  s["constraints"] = constraints;
  s["runs"] = runs_json(spec, out);
  s["feasible"] = out.feasible;
  if (out.feasible) {
    s["optimum"] = out.optimum;
    s["verification"] = out.verification;
    if (!out.verified) {
      s["nearest_passing_design"] = out.nearest;
      if (out.nearest.value("found", false)) {
        s["nearest_passing_design"]["design"] = design_cells(spec, out.nearest["x"].get<std::vector<double>>());
      }
    }
    s["optimum_spread"] = out.spread;
    s["constraints_on_search_samples"] = out.binding;
    if (!out.comparison.is_null()) s["choices_compared"] = out.comparison;
    if (spec.pareto) {
      s["pareto"] = {{"objective", {{"output", spec.objective_output}, {"statistic", spec.objective_statistic}}},
                     {"second", {{"output", spec.pareto->output}, {"statistic", spec.pareto->statistic}}},
                     {"evaluations", out.pool.size()},
                     {"points", spec.pareto->points},
                     {"front", out.front_verification}};
    }
  } else {
    s["message"] = out.message;
  }
  s["provenance"] = {{"poise_version", kVersion},
                     {"git_commit", engine::git_commit()},
                     {"optimization_file_sha1", engine::file_sha1(spec.file)},
                     {"study_file_sha1", engine::file_sha1(spec.base.file)},
                     {"threads", threads},
                     {"started", started},
                     {"finished", engine::now_iso8601()}};
  return s;
}

}  // namespace

OptimizationRun write_optimization(const OptimizationSpec& spec, const engine::RunOptions& options) {
  const int threads = options.threads > 0 ? options.threads : sampling::Cluster::default_threads();
  const std::string dir = engine::make_run_folder(options.results_root, spec.name, options.out);
  if (options.progress) {
    diagnostics::progress("poise: optimization " + spec.name + " -> " + dir + "\n  " + to_string(spec.algorithm) +
                          ", up to " + std::to_string(spec.max_evaluations) + " evaluations of " +
                          std::to_string(spec.samples) + " samples each (seed " + std::to_string(spec.seed) + ")");
  }
  const std::string started = engine::now_iso8601();
  const OptimizationOutcome out = optimize(spec, threads, options.progress);
  OptimizationRun result;
  result.dir = dir;
  result.answer = out.answer;
  result.exit_status = !out.feasible ? kExitRunFailed : out.verified ? kExitVerified : kExitNotVerified;
  write_history(spec, out, dir);
  if (spec.pareto) write_pareto_csv(spec, out, dir);
  const json summary = optimization_summary(spec, out, result.exit_status, threads, started);
  engine::write_file_atomic((fs::path(dir) / "summary.json").string(), summary.dump(2) + "\n");
  const fs::path pdir = fs::path(dir) / "plots";
  fs::create_directories(pdir);
  const std::vector<std::string> figures =
      options.plots ? optimization_plots(spec, out, pdir) : std::vector<std::string>{};
  engine::write_file_atomic((fs::path(dir) / "report.html").string(),
                            engine::optimization_report_html(summary, pdir, figures));
  if (!out.feasible) throw Error(out.message + " (history in " + dir + ")");
  return result;
}

}  // namespace poise::optimize
