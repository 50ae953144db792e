#include "optimize/optimization_output.h"

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
#include "engine/results/provenance.h"
#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"

namespace poise::optimize {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using engine::html_escape;

std::string fmt_pct(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f%%", 100.0 * fraction);
  return buf;
}

std::string objective_name(const OptimizationSpec& spec) {
  if (spec.objective_output.empty()) return "objective_sum" + (spec.variables.empty() ? "" : "_" + spec.variables[0].unit);
  std::string stat = spec.objective_statistic;
  std::replace(stat.begin(), stat.end(), '.', '_');
  return "objective." + spec.objective_output + "." + stat;
}

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
        h << ',' << (k < e.result.constraints.size()
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

std::string ci_text(const json& e) {
  char buf[160];
  const double v = e["value"].get<double>();
  if (e.contains("lo") || e.contains("hi")) {
    std::snprintf(buf, sizeof buf, "%.4g [%s, %s]", v, e.contains("lo") ? short_number(e["lo"].get<double>()).c_str() : "?",
                  e.contains("hi") ? short_number(e["hi"].get<double>()).c_str() : "?");
  } else {
    std::snprintf(buf, sizeof buf, "%.4g", v);
  }
  return buf;
}

std::string design_cells(const OptimizationSpec& spec, const std::vector<double>& x) {
  std::string s;
  for (std::size_t i = 0; i < spec.variables.size() && i < x.size(); ++i) {
    s += (s.empty() ? "" : ", ") + spec.variables[i].parameter + " = " + value_text(x[i], spec.variables[i].unit);
  }
  return s;
}

void check_table(std::ostringstream& h, const json& check) {
  h << "<table><tr><th class='l'>constraint</th><th>on fresh samples [95% CI]</th><th>stated bound</th><th>limit</th>"
       "<th class='l'>interval from</th><th class='l'>verdict</th></tr>\n";
  for (const auto& c : check["constraints"]) {
    h << "<tr><td class='l'>" << html_escape(c["name"].get<std::string>()) << "</td><td>" << ci_text(c["interval"])
      << "</td><td>" << (c.contains("bound_value") ? short_number(c["bound_value"].get<double>()) : "") << "</td><td>"
      << (c["at_least"].get<bool>() ? "&ge; " : "&le; ") << short_number(c["limit"].get<double>()) << "</td><td class='l'>"
      << html_escape(c["interval"]["method"].get<std::string>()) << "</td><td class='l'>"
      << html_escape(c["verdict"].get<std::string>()) << "</td></tr>\n";
  }
  h << "</table>\n<p>" << check["samples"] << " fresh samples (seed " << check["seed"] << "), " << check["failures"]
    << " failed (" << fmt_pct(check["failure_share"].get<double>()) << ")"
    << (check["failures_within_max_share"].get<bool>() ? "" : ", more than the study's max_failure_share") << ".</p>\n";
}

}  // namespace

OptimizationRun write_optimization(const OptimizationSpec& spec, const engine::RunOptions& options) {
  const int threads =
      options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const std::string dir = engine::make_run_folder(options.results_root, spec.name, options.out);
  if (options.progress) {
    std::fprintf(stderr, "poise: optimization %s -> %s\n  %s, up to %d evaluations of %zu samples each (seed %llu)\n",
                 spec.name.c_str(), dir.c_str(), to_string(spec.algorithm).c_str(), spec.max_evaluations, spec.samples,
                 static_cast<unsigned long long>(spec.seed));
  }
  const std::string started = engine::now_iso8601();
  const OptimizationOutcome out = optimize(spec, threads, options.progress);
  OptimizationRun result;
  result.dir = dir;
  result.answer = out.answer;
  result.exit_status = !out.feasible ? kExitRunFailed : out.verified ? kExitVerified : kExitNotVerified;
  write_history(spec, out, dir);
  if (spec.pareto) write_pareto_csv(spec, out, dir);
  // summary.json
  json s;
  s["answer"] = out.answer;
  s["verified"] = out.feasible && out.verified;
  s["exit_status"] = result.exit_status;
  s["optimization"] = {{"name", spec.name}, {"title", spec.title}, {"file", spec.file}, {"study", spec.base.file},
                       {"algorithm", to_string(spec.algorithm)}, {"algorithm_advice", algorithm_advice(spec.algorithm)},
                       {"samples_per_evaluation", spec.samples}, {"seed", spec.seed},
                       {"replicate_size", spec.base.replicate_size}, {"max_failure_share", spec.max_failure_share()},
                       {"common_random_numbers", true}, {"max_evaluations", spec.max_evaluations},
                       {"replicates", spec.replicates}};
  json constraints = json::array();
  for (const auto& c : spec.constraints) {
    constraints.push_back({{"name", c.name}, {"output", c.output}, {"statistic", c.statistic},
                           {"bound", to_string(c.bound)}, {"limit", c.limit()}, {"at_least", c.at_least.has_value()},
                           {"text", c.describe()}});
  }
  s["constraints"] = constraints;
  json runs = json::array();
  for (std::size_t r = 0; r < out.runs.size(); ++r) {
    const auto& run = out.runs[r];
    json x;
    for (std::size_t i = 0; i < spec.variables.size() && i < run.result.x.size(); ++i) {
      x[spec.variables[i].parameter] = value_text(run.result.x[i], spec.variables[i].unit);
    }
    runs.push_back({{"choice", run.choice}, {"label", choice_label(run.choice)}, {"status", run.result.status},
                    {"evaluations", run.result.evaluations}, {"feasible", run.result.feasible}, {"x", x},
                    {"objective", run.result.feasible ? json(run.result.best.objective) : json(nullptr)},
                    {"headline", out.feasible && r == out.best}, {"optimization_pick", out.feasible && r == out.optimization_pick}});
  }
  s["runs"] = runs;
  s["feasible"] = out.feasible;
  if (out.feasible) {
    s["optimum"] = out.optimum;
    s["verification"] = out.verification;
    if (!out.verified) s["nearest_passing_design"] = out.nearest;
    s["optimum_spread"] = out.spread;
    s["constraints_on_search_samples"] = out.binding;
    if (!out.comparison.is_null()) s["choices_compared"] = out.comparison;
    if (spec.pareto) {
      s["pareto"] = {{"objective", {{"output", spec.objective_output}, {"statistic", spec.objective_statistic}}},
                     {"second", {{"output", spec.pareto->output}, {"statistic", spec.pareto->statistic}}},
                     {"evaluations", out.pool.size()}, {"front", out.front_verification}};
    }
  } else {
    s["message"] = out.message;
  }
  s["provenance"] = {{"poise_version", kVersion}, {"git_commit", engine::git_commit()},
                     {"optimization_file_sha1", engine::file_sha1(spec.file)},
                     {"study_file_sha1", engine::file_sha1(spec.base.file)}, {"threads", threads},
                     {"started", started}, {"finished", engine::now_iso8601()}};
  engine::write_file_atomic((fs::path(dir) / "summary.json").string(), s.dump(2) + "\n");
  // Plots.
  const fs::path pdir = fs::path(dir) / "plots";
  fs::create_directories(pdir);
  std::vector<std::string> figures;
  if (options.plots) {
    std::ostringstream d;
    for (std::size_t r = 0; r < out.runs.size(); ++r) {
      double best = INFINITY;
      for (const auto& e : out.runs[r].result.history) {
        if (e.feasible) best = std::min(best, e.result.objective);
        d << e.evaluation << ' ' << (e.result.ok ? e.result.objective : NAN) << ' ' << (e.feasible ? 1 : 0) << ' '
          << (std::isfinite(best) ? best : NAN) << '\n';
      }
      d << "\n\n";
    }
    engine::write_file_atomic((pdir / "convergence.dat").string(), d.str());
    std::ostringstream titles;
    for (std::size_t r = 0; r < out.runs.size(); ++r) {
      titles << (r ? " " : "") << '"' << choice_label(out.runs[r].choice) << '"';
    }
    std::ostringstream cgp;
    cgp << "set terminal svg size 720,420 dynamic noenhanced font 'Helvetica,12'\nset output 'convergence.svg'\n"
           "set grid\nset title 'Convergence'\nset xlabel 'evaluation'\nset ylabel '" << objective_name(spec)
        << "'\nset key outside bottom center horizontal\nlabels = '" << titles.str() << "'\n"
           "plot for [i=0:" << out.runs.size() - 1 << "] 'convergence.dat' index i u 1:($3 > 0 ? $2 : 1/0) w p pt 7 title sprintf('feasible (%s)', word(labels, i+1)), "
           "for [i=0:" << out.runs.size() - 1 << "] 'convergence.dat' index i u 1:($3 > 0 ? 1/0 : $2) w p pt 6 lc rgb 'gray' notitle, "
           "for [i=0:" << out.runs.size() - 1 << "] 'convergence.dat' index i u 1:4 w steps lw 2 notitle\n";
    engine::write_file_atomic((pdir / "convergence.gp").string(), cgp.str());
    std::string why;
    if (engine::run_gnuplot((pdir / "convergence.gp").string(), &why)) figures.push_back("convergence.svg");
    if (spec.pareto && out.feasible) {
      std::ostringstream d2;
      for (const auto& q : out.pool) {
        if (q.feasible) d2 << q.second << ' ' << q.objective << ' ' << q.choice << '\n';
      }
      d2 << "\n\n";
      for (const auto& f : out.front_verification) {
        const json& o = f["objective"];
        const double v = o["value"].get<double>();
        d2 << f["second_optimization"].get<double>() << ' ' << v << ' ' << o.value("lo", v) << ' ' << o.value("hi", v)
           << ' ' << f["objective_optimization"].get<double>() << '\n';
      }
      engine::write_file_atomic((pdir / "pareto.dat").string(), d2.str());
      const std::string xl = spec.pareto->statistic + " of " + spec.pareto->output + " [" +
                             output_unit(spec, spec.pareto->output) + "]";
      const std::string yl = spec.objective_statistic + " of " + spec.objective_output + " [" +
                             output_unit(spec, spec.objective_output) + "]";
      std::ostringstream pgp;
      pgp << "set terminal svg size 760,480 dynamic noenhanced font 'Helvetica,12'\nset output 'pareto.svg'\n"
             "set grid\nset title 'Pareto front'\nset xlabel '" << xl << "'\nset ylabel '" << yl
          << "'\nset key outside bottom center horizontal\n"
             "plot 'pareto.dat' index 0 u 1:2:3 w p pt 7 ps 0.6 lc variable title 'feasible evaluations (colour: choice)', "
             "'pareto.dat' index 1 u 1:5 w lp pt 6 ps 1.2 lc rgb 'black' title 'front (optimization samples)', "
             "'pareto.dat' index 1 u 1:2:3:4 w yerrorbars pt 7 lc rgb 'red' title 'front on fresh samples, 95% CI'\n";
      engine::write_file_atomic((pdir / "pareto.gp").string(), pgp.str());
      if (engine::run_gnuplot((pdir / "pareto.gp").string(), &why)) figures.push_back("pareto.svg");
    }
  }
  // report.html: the answer first.
  std::ostringstream h;
  h << "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>Poise: " << html_escape(spec.name)
    << "</title><style>body{font-family:Helvetica,Arial,sans-serif;max-width:1100px;margin:2em auto;color:#222}"
       "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}th{background:#eef}"
       "td.l,th.l{text-align:left}pre{background:#f6f6f6;padding:0.8em;white-space:pre-wrap}"
       ".answer{font-size:1.15em;border-left:5px solid #36c;padding:0.5em 1em;background:#f3f6ff}"
       ".bad{border-left-color:#c33;background:#fff3f3}</style></head><body>\n<h1>"
    << html_escape(spec.title.empty() ? spec.name : spec.title) << "</h1>\n";
  const bool good = out.feasible && out.verified;
  h << "<p class='answer" << (good ? "" : " bad") << "'><b>"
    << (!out.feasible ? "No feasible design." : out.verified ? "Verified on fresh samples." : "Design NOT verified on fresh samples (exit status 3).")
    << "</b> " << html_escape(out.answer) << "</p>\n";
  h << "<p>Optimization <code>" << html_escape(spec.file) << "</code> over the study <code>" << html_escape(spec.base.file)
    << "</code>: " << to_string(spec.algorithm) << " (" << html_escape(algorithm_advice(spec.algorithm)) << "), "
    << spec.samples << " samples per evaluation with common random numbers (seed " << spec.seed << ")"
    << (spec.base.replicate_size > 0 ? ", intervals from randomized replicates of " + std::to_string(spec.base.replicate_size) + " samples" : "")
    << "; an evaluation with more than " << fmt_pct(spec.max_failure_share()) << " failed samples counts as failed.</p>\n";
  if (out.feasible) {
    h << "<h2>Fresh-sample check of the answer's design</h2>\n";
    check_table(h, out.verification);
    if (!out.verified) {
      h << "<h3>Nearest design that passes</h3>\n";
      if (out.nearest.value("found", false)) {
        h << "<p>Found by tightening each constraint that did not pass by its excess over the limit, searching again "
             "from the optimum, checking on the same fresh samples and re-checking on "
          << spec.verification_samples << " other fresh samples (seed " << spec.recheck_seed() << "): <b>"
          << html_escape(design_cells(spec, out.nearest["x"].get<std::vector<double>>())) << "</b>.</p>\n";
        check_table(h, out.nearest["recheck"]);
      } else {
        h << "<p>None found: " << html_escape(out.nearest.value("why", std::string())) << ".</p>\n";
      }
    }
    h << "<h2>The optimum's own uncertainty</h2>\n";
    if (out.spread.contains("variables")) {
      h << "<p>The search of the headline combination run with " << out.spread["searches"]
        << " independent seeds (the optimum is set by the draw as much as by the design): the spread of each variable "
           "and of the objective, and the step the answer is rounded to (the power of ten at or below the range).</p>\n"
           "<table><tr><th class='l'>variable</th><th>min</th><th>max</th><th>std</th><th>answer rounded to</th></tr>\n";
      for (const auto& v : out.spread["variables"]) {
        h << "<tr><td class='l'>" << html_escape(v["parameter"].get<std::string>()) << " [" << html_escape(v["unit"].get<std::string>())
          << "]</td><td>" << short_number(v["min"].get<double>()) << "</td><td>" << short_number(v["max"].get<double>())
          << "</td><td>" << short_number(v["std"].get<double>()) << "</td><td>" << short_number(v["supported_step"].get<double>())
          << "</td></tr>\n";
      }
      const json& o = out.spread["objective"];
      h << "<tr><td class='l'>objective (own samples)</td><td>" << short_number(o["min"].get<double>()) << "</td><td>"
        << short_number(o["max"].get<double>()) << "</td><td>" << short_number(o["std"].get<double>()) << "</td><td>"
        << short_number(o["supported_step"].get<double>()) << "</td></tr>\n</table>\n";
    } else {
      h << "<p>One search ([optimization] replicates = 1): the spread of the optimum over seeds was not measured.</p>\n";
    }
    h << "<p>Constraints at the optimum on the search's own " << spec.samples << " samples (95% intervals; binding: within 2% of the limit):</p><ul>\n";
    for (const auto& b : out.binding) {
      h << "<li>" << html_escape(b["text"].get<std::string>()) << (b["binding"].get<bool>() ? " <b>(binding)</b>" : "") << "</li>\n";
    }
    h << "</ul>\n";
  }
  h << "<h2>Searches</h2>\n<table><tr><th class='l'>choice</th><th class='l'>status</th><th>evaluations</th><th>feasible</th>"
       "<th class='l'>design</th><th>objective (search samples)</th></tr>\n";
  for (std::size_t r = 0; r < out.runs.size(); ++r) {
    const auto& run = out.runs[r];
    h << "<tr><td class='l'>" << html_escape(choice_label(run.choice))
      << (out.feasible && r == out.best ? " (headline)" : "") << (out.feasible && r == out.optimization_pick ? " (search's pick)" : "")
      << "</td><td class='l'>" << html_escape(run.result.status) << "</td><td>" << run.result.evaluations << "</td><td>"
      << (run.result.feasible ? "yes" : "no") << "</td><td class='l'>" << html_escape(design_cells(spec, run.result.x))
      << "</td><td>" << (run.result.feasible ? short_number(run.result.best.objective) : "") << "</td></tr>\n";
  }
  h << "</table>\n";
  if (!out.comparison.is_null()) {
    h << "<h2>Choices decided on fresh samples</h2>\n<p>Each combination's best design (from its search) run on two "
         "independent fresh sets of " << spec.verification_samples << " samples: the <i>selection set</i> (seed "
      << spec.selection_seed() << ") picks the headline and, per value of a choice parameter, its best combination; the "
         "<i>comparison set</i> (seed " << spec.verification_seed << ") compares them, so no figure below was used to "
         "pick what it describes. Differences are paired (same units), bootstrap 95% intervals; 'bootstrap share' is the "
         "share of bootstrap resamples in which the headline stays ahead: a resampling share, not a probability that it "
         "is better. Constraints are re-checked on the comparison set.</p>\n"
         "<table><tr><th class='l'>choice</th><th>selection set</th><th>comparison set [95% CI]</th>"
      << (spec.pareto ? "<th>second objective</th>" : "") << "<th>minus headline [95% CI]</th><th>bootstrap share headline ahead</th>"
         "<th class='l'>constraints</th></tr>\n";
    for (const auto& r : out.comparison["choices"]) {
      h << "<tr><td class='l'>" << html_escape(r["label"].get<std::string>()) << (r["best"].get<bool>() ? " (headline)" : "")
        << (r["optimization_pick"].get<bool>() ? " (search's pick)" : "") << "</td>";
      if (!r.contains("comparison")) {
        h << "<td colspan='5'>no feasible design</td></tr>\n";
        continue;
      }
      h << "<td>" << short_number(r["selection"]["objective"].get<double>()) << "</td><td>" << ci_text(r["objective"]) << "</td>";
      if (spec.pareto) h << "<td>" << (r.contains("second") ? ci_text(r["second"]) : "") << "</td>";
      if (r.contains("minus_best")) {
        const json& d = r["minus_best"];
        json dd{{"value", d["difference"]}};
        if (d.contains("lo")) dd["lo"] = d["lo"];
        if (d.contains("hi")) dd["hi"] = d["hi"];
        h << "<td>" << ci_text(dd) << "</td><td>"
          << (d.contains("bootstrap_share_reference_ahead") ? fmt_pct(d["bootstrap_share_reference_ahead"].get<double>()) : "")
          << "</td>";
      } else {
        h << "<td>(headline)</td><td></td>";
      }
      h << "<td class='l'>" << html_escape(r["comparison"]["verdict"].get<std::string>()) << "</td></tr>\n";
    }
    h << "</table>\n";
    for (const auto& p : out.comparison.value("by_parameter", json::array())) {
      h << "<p><b>" << html_escape(p["parameter"].get<std::string>()) << "</b>: each value's best combination (picked on "
           "the selection set) against the headline's value, equivalence margin " << html_escape(spec.equivalence_margin_text)
        << ":</p>\n<ul>\n";
      for (const auto& v : p["values"]) {
        h << "<li>" << html_escape(v["value"].get<std::string>()) << ": ";
        if (!v.contains("run")) {
          h << "no feasible design</li>\n";
          continue;
        }
        h << html_escape(v["label"].get<std::string>()) << ", " << ci_text(v["objective"]);
        if (v.contains("equivalence")) h << "; " << html_escape(v["equivalence"]["text"].get<std::string>());
        if (v["headline_value"].get<bool>()) h << " (headline)";
        h << "</li>\n";
      }
      h << "</ul>\n";
    }
  }
  if (spec.pareto && out.feasible) {
    h << "<h2>Pareto front</h2>\n<p>" << out.pool.size() << " evaluations (the objective, the second objective, and "
      << spec.pareto->points << " epsilon-constrained searches per choice); the front is the feasible evaluations no "
         "other beats on both. Each front point run on the comparison set (95% intervals).</p>\n"
         "<table><tr><th class='l'>choice</th><th class='l'>design</th><th>"
      << html_escape(spec.pareto->statistic + " " + spec.pareto->output) << "</th><th>"
      << html_escape(spec.objective_statistic + " " + spec.objective_output)
      << " (search samples)</th><th>fresh samples [95% CI]</th><th class='l'>constraints</th></tr>\n";
    for (const auto& f : out.front_verification) {
      h << "<tr><td class='l'>" << html_escape(f["label"].get<std::string>()) << "</td><td class='l'>"
        << html_escape(f["x"].dump()) << "</td><td>" << (f.contains("second") ? ci_text(f["second"]) : "") << "</td><td>"
        << short_number(f["objective_optimization"].get<double>()) << "</td><td>" << ci_text(f["objective"])
        << "</td><td class='l'>" << html_escape(f["constraints_verdict"].get<std::string>()) << "</td></tr>\n";
    }
    h << "</table>\n";
  }
  if (!out.feasible) h << "<h2>No feasible design</h2>\n<p>" << html_escape(out.message) << "</p>\n";
  h << engine::figures_html(pdir, figures);
  if (!spec.notes.empty()) h << "<h2>Notes</h2>\n<pre>" << html_escape(spec.notes) << "</pre>\n";
  h << "</body></html>\n";
  engine::write_file_atomic((fs::path(dir) / "report.html").string(), h.str());
  if (!out.feasible) throw Error(out.message + " (history in " + dir + ")");
  return result;
}

}  // namespace poise::optimize
