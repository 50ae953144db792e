#include "optimize/optimization_study.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "core/units.h"
#include "core/version.h"
#include "sampling/statistics.h"
#include "studies/provenance.h"
#include "studies/report.h"
#include "studies/result_io.h"
#include "studies/study_evaluation.h"
#include "studies/toml_reader.h"

namespace poise::optimize {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using studies::TomlReader;

// "3 mm" -> (3, "mm"); "0.5" -> (0.5, "").
std::pair<double, std::string> number_and_unit(TomlReader& t, const std::string& key, bool* ok) {
  const std::string text = t.string(key);
  std::istringstream in(text);
  double v = NAN;
  in >> v;
  std::string unit;
  std::getline(in >> std::ws, unit);
  *ok = static_cast<bool>(in) || in.eof();
  if (!std::isfinite(v)) {
    t.error(key, "\"" + text + "\"", "a number with its unit, e.g. \"4 mm\"");
    *ok = false;
  } else if (!unit.empty()) {
    try {
      units::unit_factor(unit);
    } catch (const Error& e) {
      t.error(key, "\"" + text + "\"", std::string("a known unit (") + e.what() + ")");
      *ok = false;
    }
  }
  return {v, unit};
}

std::string override_text(double value, const std::string& unit) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", value);
  return unit.empty() ? std::string(buf) : std::string(buf) + " " + unit;
}

}  // namespace

OptimizationSpec load_optimization(const std::string& path) {
  toml::table doc = studies::parse_toml_file(path);
  auto ctx = std::make_shared<studies::ReadContext>();
  ctx->file = path;
  TomlReader root(doc, ctx);
  OptimizationSpec s;
  s.file = path;
  std::string study_path;
  {
    TomlReader t = root.table("optimization");
    s.name = t.string("name");
    s.title = t.string("title", "");
    s.notes = t.string("notes", "");
    const std::string study = t.string("study");
    study_path = (fs::path(path).parent_path() / study).lexically_normal().string();
    if (!study.empty() && !fs::exists(study_path)) {
      t.error("study", "\"" + study + "\"", "an existing study file (looked for " + study_path + ")");
      study_path.clear();
    }
    s.samples = static_cast<std::size_t>(t.integer("samples", 2, 100'000'000));
    s.seed = static_cast<std::uint64_t>(t.integer("seed", 0, INT64_MAX));
    const std::string algo = t.choice("algorithm", {"cobyla", "bobyqa", "sbplx", "neldermead", "direct_l", "isres"});
    s.algorithm = parse_algorithm(algo);
    s.max_evaluations = static_cast<int>(t.integer("max_evaluations", 1, 1'000'000));
    s.xtol_rel = t.number("xtol_rel", [](double v) { return v > 0 && v < 1 ? "" : "0 < xtol_rel < 1"; }, 1e-3);
  }
  for (auto& v : root.table_array("variable")) {
    DesignVariable d;
    d.parameter = v.string("parameter");
    bool ok1 = true, ok2 = true, ok3 = true;
    auto [lo, u1] = number_and_unit(v, "lower", &ok1);
    auto [hi, u2] = number_and_unit(v, "upper", &ok2);
    auto [st, u3] = number_and_unit(v, "start", &ok3);
    if (ok1 && ok2 && ok3) {
      if (u1 != u2 || u1 != u3) v.error("upper", "\"" + u2 + "\"", "lower, upper and start in the same unit (\"" + u1 + "\")");
      if (!(lo < hi)) v.error("upper", override_text(hi, u2), "upper > lower");
      if (!(st >= lo && st <= hi)) v.error("start", override_text(st, u3), "start within [lower, upper]");
    }
    d.unit = u1;
    d.lower = lo;
    d.upper = hi;
    d.start = st;
    s.variables.push_back(d);
  }
  for (auto& c : root.table_array("choice")) {
    Choice ch;
    ch.parameter = c.string("parameter");
    ch.values = c.string_array("values");
    if (ch.values.empty()) c.error("values", "[]", "at least one value");
    s.choices.push_back(ch);
  }
  if (s.variables.empty()) root.error("variable", "", "at least one [[variable]] (a design variable with bounds)");
  {
    TomlReader t = root.table("objective");
    if (t.has("variable_sum")) {
      s.variable_sum = t.string_array("variable_sum");
      for (const auto& key : s.variable_sum) {
        if (std::none_of(s.variables.begin(), s.variables.end(), [&](const auto& v) { return v.parameter == key; })) {
          t.error("variable_sum", "\"" + key + "\"", "the parameter of a [[variable]]");
        }
      }
      if (t.has("output")) t.error("output", "", "either output (with statistic) or variable_sum, not both");
    } else {
      s.objective_output = t.string("output");
      s.objective_statistic = t.string("statistic");
      if (!studies::is_statistic(s.objective_statistic)) {
        t.error("statistic", "\"" + s.objective_statistic + "\"", "mean, std, min, max, p<q> (p95, p99.73), fraction_le:<x>, fraction_ge:<x>");
      }
    }
  }
  for (auto& c : root.table_array("constraint")) {
    Requirement r;
    r.output = c.string("output");
    r.statistic = c.string("statistic");
    if (!studies::is_statistic(r.statistic)) {
      c.error("statistic", "\"" + r.statistic + "\"", "mean, std, min, max, p<q>, fraction_le:<x>, fraction_ge:<x>");
    }
    if (c.has("at_least")) r.at_least = c.number("at_least");
    if (c.has("at_most")) r.at_most = c.number("at_most");
    if (r.at_least.has_value() == r.at_most.has_value()) c.error("at_least", "", "exactly one of at_least and at_most");
    s.constraints.push_back(r);
  }
  if (root.has("verification")) {
    TomlReader t = root.table("verification");
    s.verification_samples = static_cast<std::size_t>(t.integer("samples", 2, 100'000'000));
    s.verification_seed = static_cast<std::uint64_t>(t.integer("seed", 0, INT64_MAX));
  }
  studies::finish(doc, *ctx);
  // The base study, its model with the start values, and the outputs named.
  s.base = studies::load_study(study_path);
  std::map<std::string, std::string> start;
  for (const auto& v : s.variables) start[v.parameter] = override_text(v.start, v.unit);
  for (const auto& c : s.choices) start[c.parameter] = c.values.front();
  studies::StudyConfig base = s.base;
  for (const auto& [k, v] : start) base.overrides[k] = v;
  const std::vector<std::string> names = studies::study_output_names(base);
  std::vector<InputError> errors;
  auto check_output = [&](const std::string& output, const std::string& key) {
    if (std::find(names.begin(), names.end(), output) == names.end()) {
      std::string all;
      for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
      errors.emplace_back(SourceLocation{path, 0, 0}, key, "\"" + output + "\"", "an output of " + study_path + ": " + all);
    }
  };
  if (!s.objective_output.empty()) check_output(s.objective_output, "objective.output");
  for (std::size_t i = 0; i < s.constraints.size(); ++i) {
    check_output(s.constraints[i].output, "constraint[" + std::to_string(i) + "].output");
  }
  if (!errors.empty()) throw studies::ValidationError(errors);
  return s;
}

namespace {

// Objective and constraint values of one evaluated design.
Evaluation score(const OptimizationSpec& spec, const std::vector<double>& x, const studies::StudyEvaluation& e) {
  Evaluation r;
  if (e.failures > 0 && e.failures * 2 > e.samples) {
    r.ok = false;
    r.message = std::to_string(e.failures) + " of " + std::to_string(e.samples) + " samples failed: " + e.first_failure;
    return r;
  }
  if (spec.objective_output.empty()) {
    r.objective = 0.0;
    for (std::size_t i = 0; i < spec.variables.size(); ++i) {
      if (std::find(spec.variable_sum.begin(), spec.variable_sum.end(), spec.variables[i].parameter) !=
          spec.variable_sum.end()) {
        r.objective += x[i];
      }
    }
  } else {
    r.objective = studies::statistic(e.values[e.index(spec.objective_output)], spec.objective_statistic);
  }
  for (const auto& c : spec.constraints) {
    const double v = studies::statistic(e.values[e.index(c.output)], c.statistic);
    r.constraints.push_back(c.at_least ? *c.at_least - v : v - *c.at_most);
  }
  return r;
}

std::map<std::string, std::string> overrides_of(const OptimizationSpec& spec, const std::vector<double>& x,
                                                const std::map<std::string, std::string>& choice) {
  std::map<std::string, std::string> o = choice;
  for (std::size_t i = 0; i < spec.variables.size(); ++i) {
    o[spec.variables[i].parameter] = override_text(x[i], spec.variables[i].unit);
  }
  return o;
}

// Every combination of the discrete choices (one empty combination if there are none).
std::vector<std::map<std::string, std::string>> combinations(const std::vector<Choice>& choices) {
  std::vector<std::map<std::string, std::string>> out{{}};
  for (const auto& c : choices) {
    std::vector<std::map<std::string, std::string>> next;
    for (const auto& partial : out) {
      for (const auto& v : c.values) {
        auto m = partial;
        m[c.parameter] = v;
        next.push_back(m);
      }
    }
    out = std::move(next);
  }
  return out;
}

std::string describe_choice(const std::map<std::string, std::string>& c) {
  std::string s;
  for (const auto& [k, v] : c) s += (s.empty() ? "" : ", ") + k + " = " + v;
  return s.empty() ? "-" : s;
}

}  // namespace

OptimizationOutcome optimize(const OptimizationSpec& spec, int threads, bool progress) {
  OptimizationOutcome out;
  std::vector<Variable> vars;
  for (const auto& v : spec.variables) vars.push_back({v.parameter, v.lower, v.upper, v.start});
  Options opt;
  opt.algorithm = spec.algorithm;
  opt.max_evaluations = spec.max_evaluations;
  opt.xtol_rel = spec.xtol_rel;
  opt.constraints = spec.constraints.size();
  opt.seed = spec.seed;
  double best_f = INFINITY;
  for (const auto& choice : combinations(spec.choices)) {
    int count = 0;
    const Problem f = [&](const std::vector<double>& x) {
      Evaluation r;
      try {
        const studies::StudyEvaluation e =
            studies::evaluate_study(spec.base, overrides_of(spec, x, choice), spec.samples, spec.seed, threads);
        r = score(spec, x, e);
      } catch (const std::exception& ex) {
        r.ok = false;
        r.message = ex.what();
      }
      ++count;
      if (progress) {
        std::string xs;
        for (std::size_t i = 0; i < x.size(); ++i) xs += (i ? ", " : "") + override_text(x[i], spec.variables[i].unit);
        bool feasible = r.ok;
        for (double c : r.constraints) feasible = feasible && c <= 0.0;
        std::fprintf(stderr, "  [%s] evaluation %d/%d: %s -> %s%s\n", describe_choice(choice).c_str(), count,
                     spec.max_evaluations, xs.c_str(), r.ok ? override_text(r.objective, "").c_str() : r.message.c_str(),
                     r.ok ? (feasible ? "" : " (infeasible)") : "");
      }
      return r;
    };
    ChoiceResult cr{choice, minimize(f, vars, opt)};
    if (cr.result.feasible && cr.result.best.objective < best_f) {
      best_f = cr.result.best.objective;
      out.best = out.runs.size();
      out.feasible = true;
    }
    out.runs.push_back(std::move(cr));
  }
  if (!out.feasible) {
    // The least violating evaluation, to say how far the requirements are.
    std::string closest;
    double least = INFINITY;
    for (const auto& run : out.runs) {
      for (const auto& h : run.result.history) {
        if (!h.result.ok) continue;
        double worst = 0.0;
        std::size_t which = 0;
        for (std::size_t k = 0; k < h.result.constraints.size(); ++k) {
          if (h.result.constraints[k] > worst) {
            worst = h.result.constraints[k];
            which = k;
          }
        }
        if (worst < least && !spec.constraints.empty()) {
          least = worst;
          const auto& c = spec.constraints[which];
          closest = c.statistic + " of " + c.output + (c.at_least ? " >= " : " <= ") +
                    override_text(c.at_least ? *c.at_least : *c.at_most, "") + " missed by " + override_text(worst, "");
        }
      }
    }
    out.message = "no design met the constraints in " + std::to_string(spec.max_evaluations) +
                  " evaluations per choice" + (closest.empty() ? "" : "; closest: " + closest) +
                  ". Relax a constraint, widen the bounds or change the algorithm (a global one: direct_l, isres).";
    return out;
  }
  const ChoiceResult& best = out.runs[out.best];
  out.optimum = overrides_of(spec, best.result.x, best.choice);
  // Verification with fresh random numbers and more samples.
  const studies::StudyEvaluation e = studies::evaluate_study(spec.base, out.optimum, spec.verification_samples,
                                                             spec.verification_seed, threads);
  json v{{"samples", spec.verification_samples}, {"seed", spec.verification_seed}, {"failures", e.failures}};
  auto add = [&](const std::string& role, const std::string& output, const std::string& stat) {
    const auto& values = e.values[e.index(output)];
    json j{{"role", role}, {"output", output}, {"statistic", stat}, {"value", studies::statistic(values, stat)},
           {"summary", studies::summary_json(sampling::summarize(values))}};
    v["figures"].push_back(j);
  };
  if (!spec.objective_output.empty()) add("objective", spec.objective_output, spec.objective_statistic);
  for (const auto& c : spec.constraints) add("constraint", c.output, c.statistic);
  bool still = true;
  std::size_t k = spec.objective_output.empty() ? 0 : 1;
  for (const auto& c : spec.constraints) {
    const double val = v["figures"][k++]["value"].get<double>();
    still = still && (c.at_least ? val >= *c.at_least : val <= *c.at_most);
  }
  v["constraints_met"] = still;
  out.verification = v;
  return out;
}

std::string run_optimization(const std::string& path, const studies::RunOptions& options) {
  const OptimizationSpec spec = load_optimization(path);
  const int threads =
      options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const std::string dir = studies::make_run_folder(options.results_root, spec.name, options.out);
  if (options.progress) {
    std::fprintf(stderr, "poise: optimization %s -> %s\n  %s, up to %d evaluations of %zu samples each (seed %llu)\n",
                 spec.name.c_str(), dir.c_str(), to_string(spec.algorithm).c_str(), spec.max_evaluations, spec.samples,
                 static_cast<unsigned long long>(spec.seed));
  }
  const std::string started = studies::now_iso8601();
  const OptimizationOutcome out = optimize(spec, threads, options.progress);

  // history.csv
  {
    std::ofstream h(fs::path(dir) / "history.csv");
    h << "choice,evaluation";
    for (const auto& v : spec.variables) h << ',' << v.parameter << (v.unit.empty() ? "" : "_" + v.unit);
    h << ",objective";
    for (std::size_t k = 0; k < spec.constraints.size(); ++k) h << ",constraint_" << k;
    h << ",feasible,message\n";
    for (std::size_t r = 0; r < out.runs.size(); ++r) {
      for (const auto& e : out.runs[r].result.history) {
        h << r << ',' << e.evaluation;
        for (double x : e.x) h << ',' << studies::csv_number(x);
        h << ',' << studies::csv_number(e.result.objective);
        for (std::size_t k = 0; k < spec.constraints.size(); ++k) {
          h << ',' << (k < e.result.constraints.size() ? studies::csv_number(e.result.constraints[k]) : "");
        }
        h << ',' << (e.feasible ? 1 : 0) << ',' << studies::csv_text(e.result.message) << '\n';
      }
    }
  }
  // summary.json
  json s;
  s["optimization"] = {{"name", spec.name}, {"title", spec.title}, {"file", spec.file}, {"study", spec.base.file},
                       {"algorithm", to_string(spec.algorithm)}, {"algorithm_advice", algorithm_advice(spec.algorithm)},
                       {"samples_per_evaluation", spec.samples}, {"seed", spec.seed},
                       {"common_random_numbers", true}, {"max_evaluations", spec.max_evaluations}};
  json runs = json::array();
  for (const auto& r : out.runs) {
    json x;
    for (std::size_t i = 0; i < spec.variables.size() && i < r.result.x.size(); ++i) {
      x[spec.variables[i].parameter] = override_text(r.result.x[i], spec.variables[i].unit);
    }
    runs.push_back({{"choice", r.choice}, {"status", r.result.status}, {"evaluations", r.result.evaluations},
                    {"feasible", r.result.feasible}, {"x", x},
                    {"objective", r.result.feasible ? json(r.result.best.objective) : json(nullptr)}});
  }
  s["runs"] = runs;
  s["feasible"] = out.feasible;
  if (out.feasible) {
    s["optimum"] = out.optimum;
    s["verification"] = out.verification;
  } else {
    s["message"] = out.message;
  }
  s["provenance"] = {{"poise_version", kVersion}, {"git_commit", studies::git_commit()},
                     {"optimization_file_sha1", studies::file_sha1(spec.file)},
                     {"study_file_sha1", studies::file_sha1(spec.base.file)}, {"threads", threads},
                     {"started", started}, {"finished", studies::now_iso8601()}};
  std::ofstream(fs::path(dir) / "summary.json") << s.dump(2) << '\n';
  // Convergence plot and report.
  const fs::path pdir = fs::path(dir) / "plots";
  fs::create_directories(pdir);
  std::vector<std::string> figures;
  if (options.plots) {
    std::ofstream d(pdir / "convergence.dat");
    for (std::size_t r = 0; r < out.runs.size(); ++r) {
      double best = INFINITY;
      for (const auto& e : out.runs[r].result.history) {
        if (e.feasible) best = std::min(best, e.result.objective);
        d << e.evaluation << ' ' << (e.result.ok ? e.result.objective : NAN) << ' ' << (e.feasible ? 1 : 0) << ' '
          << (std::isfinite(best) ? best : NAN) << '\n';
      }
      d << "\n\n";
    }
    d.close();
    std::ofstream(pdir / "convergence.gp")
        << "set terminal svg size 720,420 dynamic noenhanced font 'Helvetica,12'\nset output 'convergence.svg'\n"
           "set grid\nset title 'Convergence'\nset xlabel 'evaluation'\nset ylabel 'objective'\nset key outside bottom center horizontal\n"
           "plot for [i=0:" << out.runs.size() - 1 << "] 'convergence.dat' index i u 1:($3 > 0 ? $2 : 1/0) w p pt 7 title sprintf('feasible (choice %d)', i), "
           "for [i=0:" << out.runs.size() - 1 << "] 'convergence.dat' index i u 1:($3 > 0 ? 1/0 : $2) w p pt 6 lc rgb 'gray' title sprintf('infeasible (choice %d)', i), "
           "for [i=0:" << out.runs.size() - 1 << "] 'convergence.dat' index i u 1:4 w steps lw 2 title sprintf('best feasible (choice %d)', i)\n";
    std::string why;
    if (studies::run_gnuplot((pdir / "convergence.gp").string(), &why)) figures.push_back("convergence.svg");
  }
  std::ostringstream h;
  h << "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>Poise: " << studies::html_escape(spec.name)
    << "</title><style>body{font-family:Helvetica,Arial,sans-serif;max-width:1100px;margin:2em auto;color:#222}"
       "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}th{background:#eef}"
       "td.l,th.l{text-align:left}pre{background:#f6f6f6;padding:0.8em;white-space:pre-wrap}</style></head><body>\n<h1>"
    << studies::html_escape(spec.title.empty() ? spec.name : spec.title) << "</h1>\n<p>Optimization <code>"
    << studies::html_escape(spec.file) << "</code> over the study <code>" << studies::html_escape(spec.base.file)
    << "</code>: " << to_string(spec.algorithm) << " (" << studies::html_escape(algorithm_advice(spec.algorithm))
    << "), " << spec.samples << " samples per evaluation with common random numbers (seed " << spec.seed << ").</p>\n";
  h << "<h2>Runs</h2>\n<table><tr><th class='l'>choice</th><th class='l'>status</th><th>evaluations</th><th>feasible</th>"
       "<th class='l'>design</th><th>objective</th></tr>\n";
  for (const auto& r : runs) {
    h << "<tr><td class='l'>" << studies::html_escape(r["choice"].dump()) << "</td><td class='l'>"
      << studies::html_escape(r["status"].get<std::string>()) << "</td><td>" << r["evaluations"] << "</td><td>"
      << (r["feasible"].get<bool>() ? "yes" : "no") << "</td><td class='l'>" << studies::html_escape(r["x"].dump())
      << "</td><td>" << studies::html_escape(r["objective"].dump()) << "</td></tr>\n";
  }
  h << "</table>\n";
  if (out.feasible) {
    h << "<h2>Optimum, verified with fresh random numbers</h2>\n<pre>" << studies::html_escape(json(out.optimum).dump(2))
      << "</pre>\n<pre>" << studies::html_escape(out.verification.dump(2)) << "</pre>\n";
  } else {
    h << "<h2>No feasible design</h2>\n<p>" << studies::html_escape(out.message) << "</p>\n";
  }
  for (const auto& f : figures) h << "<p><img src='plots/" << f << "' alt='" << f << "'></p>\n";
  if (!spec.notes.empty()) h << "<h2>Notes</h2>\n<pre>" << studies::html_escape(spec.notes) << "</pre>\n";
  h << "</body></html>\n";
  std::ofstream(fs::path(dir) / "report.html") << h.str();
  if (!out.feasible) throw Error(out.message + " (history in " + dir + ")");
  return dir;
}

}  // namespace poise::optimize
