#include "optimize/optimization_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "core/units.h"
#include "core/version.h"
#include "sampling/random_stream.h"
#include "sampling/statistics.h"
#include "engine/procedure_study.h"
#include "engine/provenance.h"
#include "engine/report_plot.h"
#include "engine/result_io.h"
#include "engine/study_evaluation.h"
#include "engine/toml_reader.h"

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

std::string fmt_pct(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f%%", 100.0 * fraction);
  return buf;
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
  if (root.has("pareto")) {
    TomlReader t = root.table("pareto");
    ParetoSpec p;
    p.output = t.string("output");
    p.statistic = t.string("statistic");
    if (!studies::is_statistic(p.statistic)) {
      t.error("statistic", "\"" + p.statistic + "\"", "mean, std, min, max, p<q> (p95, p99.73), fraction_le:<x>, fraction_ge:<x>");
    }
    p.points = static_cast<int>(t.integer("points", 0, 50, 3));
    t.string("notes", "");
    s.pareto = p;
  }
  if (root.has("overrides")) {
    TomlReader t = root.table("overrides");
    for (const auto& key : t.keys()) s.overrides[key] = t.string(key);
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
  for (const auto& [k, v] : s.overrides) base.overrides[k] = v;
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
  if (s.pareto) check_output(s.pareto->output, "pareto.output");
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
  std::map<std::string, std::string> o = spec.overrides;
  for (const auto& [k, v] : choice) o[k] = v;
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

nlohmann::json statistic_with_ci(const std::vector<double>& values, const std::string& stat, std::uint64_t seed,
                                 int resamples) {
  json j{{"value", studies::statistic(values, stat)}};
  if (values.size() < 2) return j;
  sampling::RandomStream rs(seed, sampling::StreamId::kBootstrap, 0);
  std::vector<double> boot(static_cast<std::size_t>(resamples)), r(values.size());
  for (auto& b : boot) {
    for (auto& v : r) v = values[static_cast<std::size_t>(rs.uniform() * static_cast<double>(values.size()))];
    b = studies::statistic(r, stat);
  }
  std::sort(boot.begin(), boot.end());
  j["lo"] = sampling::quantile_sorted(boot, 0.025).value;
  j["hi"] = sampling::quantile_sorted(boot, 0.975).value;
  return j;
}

namespace {

// Paired bootstrap of stat(a) - stat(b) over the same samples (a and b from the same random
// numbers, no failures); unpaired if the sizes differ.
json paired_difference(const std::vector<double>& a, const std::vector<double>& b, const std::string& stat,
                       std::uint64_t seed, int resamples = 1000) {
  const bool paired = a.size() == b.size();
  json j{{"difference", studies::statistic(a, stat) - studies::statistic(b, stat)}, {"paired", paired}};
  if (a.size() < 2 || b.size() < 2) return j;
  sampling::RandomStream rs(seed, sampling::StreamId::kBootstrap, 1);
  std::vector<double> d(static_cast<std::size_t>(resamples)), ra(a.size()), rb(b.size());
  std::size_t ahead = 0;
  for (auto& x : d) {
    for (std::size_t k = 0; k < ra.size(); ++k) {
      const auto i = static_cast<std::size_t>(rs.uniform() * static_cast<double>(a.size()));
      ra[k] = a[i];
      if (paired) rb[k] = b[i];
    }
    if (!paired) {
      for (auto& v : rb) v = b[static_cast<std::size_t>(rs.uniform() * static_cast<double>(b.size()))];
    }
    x = studies::statistic(ra, stat) - studies::statistic(rb, stat);
    ahead += x > 0 ? 1 : 0;
  }
  std::sort(d.begin(), d.end());
  j["lo"] = sampling::quantile_sorted(d, 0.025).value;
  j["hi"] = sampling::quantile_sorted(d, 0.975).value;
  j["share_best_ahead"] = static_cast<double>(ahead) / static_cast<double>(resamples);
  return j;
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
  out.choices = combinations(spec.choices);
  const auto t_start = std::chrono::steady_clock::now();
  long done = 0;
  const long planned = static_cast<long>(out.choices.size()) * spec.max_evaluations *
                       (spec.pareto ? 2 + spec.pareto->points : 1);
  // Every design evaluated once per choice: the searches of a choice share this cache.
  struct Scored {
    Evaluation primary;   // objective + constraints
    double second = NAN;  // [pareto] statistic
  };
  double best_f = INFINITY;
  for (std::size_t ci = 0; ci < out.choices.size(); ++ci) {
    const auto& choice = out.choices[ci];
    std::map<std::vector<double>, Scored> cache;
    int count = 0;
    std::string label;  // the search running
    auto evaluate = [&](const std::vector<double>& x) -> const Scored& {
      if (auto it = cache.find(x); it != cache.end()) return it->second;
      Scored sc;
      try {
        const studies::StudyEvaluation e =
            studies::evaluate_study(spec.base, overrides_of(spec, x, choice), spec.samples, spec.seed, threads);
        sc.primary = score(spec, x, e);
        if (spec.pareto && sc.primary.ok) sc.second = studies::statistic(e.values[e.index(spec.pareto->output)], spec.pareto->statistic);
      } catch (const std::exception& ex) {
        sc.primary.ok = false;
        sc.primary.message = ex.what();
      }
      ++count;
      if (spec.pareto && sc.primary.ok) {
        ParetoPoint p{ci, label, x, sc.primary.objective, sc.second, true};
        for (double c : sc.primary.constraints) p.feasible = p.feasible && c <= opt.constraint_tolerance;
        out.pool.push_back(std::move(p));
      }
      if (progress) {
        std::string xs;
        for (std::size_t i = 0; i < x.size(); ++i) xs += (i ? ", " : "") + override_text(x[i], spec.variables[i].unit);
        bool feasible = sc.primary.ok;
        for (double c : sc.primary.constraints) feasible = feasible && c <= 0.0;
        // ETA from the mean evaluation time and the largest number still possible (searches
        // usually converge before their budget, so it is an upper bound).
        ++done;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
        const double eta = elapsed / static_cast<double>(done) * static_cast<double>(std::max(planned - done, 0L));
        std::fprintf(stderr, "  [%s] evaluation %d: %s -> %s%s%s  (%.0f s, ETA <= %.0f min)\n", describe_choice(choice).c_str(), count,
                     xs.c_str(), sc.primary.ok ? override_text(sc.primary.objective, "").c_str() : sc.primary.message.c_str(),
                     spec.pareto && sc.primary.ok ? (", " + override_text(sc.second, "")).c_str() : "",
                     sc.primary.ok ? (feasible ? "" : " (infeasible)") : "", elapsed, eta / 60.0);
      }
      return cache.emplace(x, std::move(sc)).first->second;
    };
    // A search: `what` = objective, second, or the objective with second <= level.
    auto search = [&](const std::string& what, double level, const std::vector<double>& start) {
      std::vector<Variable> v = vars;
      for (std::size_t i = 0; i < v.size(); ++i) v[i].start = start[i];
      Options o = opt;
      if (what == "epsilon") o.constraints += 1;
      const Problem f = [&](const std::vector<double>& x) {
        const Scored& sc = evaluate(x);
        Evaluation r = sc.primary;
        if (!r.ok) return r;
        if (what == "second") r.objective = sc.second;
        if (what == "epsilon") r.constraints.push_back(sc.second - level);
        return r;
      };
      label = what == "epsilon" ? "epsilon " + override_text(level, "") : what;
      return minimize(f, v, o);
    };
    std::vector<double> x0;
    for (const auto& v : vars) x0.push_back(v.start);
    ChoiceResult cr{choice, search("objective", 0.0, x0)};
    if (spec.pareto && cr.result.feasible) {
      const Result second = search("second", 0.0, x0);
      if (second.feasible) {
        const double lo = evaluate(second.x).second, hi = evaluate(cr.result.x).second;
        for (int k = 1; k <= spec.pareto->points && hi > lo; ++k) {
          search("epsilon", lo + (hi - lo) * k / (spec.pareto->points + 1), second.x);
        }
      }
    }
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
  auto verify = [&](const std::map<std::string, std::string>& design) {
    return studies::evaluate_study(spec.base, design, spec.verification_samples, spec.verification_seed, threads);
  };
  const studies::StudyEvaluation e = verify(out.optimum);
  json v{{"samples", spec.verification_samples}, {"seed", spec.verification_seed}, {"failures", e.failures}};
  auto add = [&](const std::string& role, const std::string& output, const std::string& stat) {
    const auto& values = e.values[e.index(output)];
    json j{{"role", role}, {"output", output}, {"statistic", stat}, {"value", studies::statistic(values, stat)},
           {"bootstrap", statistic_with_ci(values, stat, spec.verification_seed)},
           {"summary", studies::summary_json(sampling::summarize(values))}};
    v["figures"].push_back(j);
  };
  if (!spec.objective_output.empty()) add("objective", spec.objective_output, spec.objective_statistic);
  for (const auto& c : spec.constraints) add("constraint", c.output, c.statistic);
  if (spec.pareto) add("second objective", spec.pareto->output, spec.pareto->statistic);
  bool still = true;
  std::size_t k = spec.objective_output.empty() ? 0 : 1;
  for (const auto& c : spec.constraints) {
    const double val = v["figures"][k++]["value"].get<double>();
    still = still && (c.at_least ? val >= *c.at_least : val <= *c.at_most);
  }
  v["constraints_met"] = still;
  out.verification = v;
  // The choices compared on the same fresh random numbers. The reference is the choice best
  // on these fresh samples (the optimization's pick may differ: it was chosen on the
  // optimization samples, whose noise favours it).
  if (out.runs.size() > 1 && !spec.objective_output.empty()) {
    std::vector<std::vector<double>> verified(out.runs.size());
    std::optional<std::size_t> ref;
    json rows = json::array();
    for (std::size_t r = 0; r < out.runs.size(); ++r) {
      const ChoiceResult& run = out.runs[r];
      json row{{"choice", run.choice}, {"feasible", run.result.feasible}, {"optimization_pick", r == out.best}};
      if (run.result.feasible) {
        const studies::StudyEvaluation er = r == out.best ? e : verify(overrides_of(spec, run.result.x, run.choice));
        verified[r] = er.values[er.index(spec.objective_output)];
        row["objective"] = statistic_with_ci(verified[r], spec.objective_statistic, spec.verification_seed);
        row["failures"] = er.failures;
        if (spec.pareto) {
          row["second"] = statistic_with_ci(er.values[er.index(spec.pareto->output)], spec.pareto->statistic,
                                            spec.verification_seed);
        }
        if (!ref || row["objective"]["value"].get<double>() < rows[*ref]["objective"]["value"].get<double>()) ref = r;
      }
      rows.push_back(row);
    }
    for (std::size_t r = 0; r < out.runs.size(); ++r) {
      rows[r]["best"] = ref && r == *ref;
      if (ref && r != *ref && !verified[r].empty()) {
        rows[r]["minus_best"] = paired_difference(verified[r], verified[*ref], spec.objective_statistic, spec.verification_seed);
      }
    }
    out.comparison = {{"output", spec.objective_output}, {"statistic", spec.objective_statistic},
                      {"samples", spec.verification_samples}, {"seed", spec.verification_seed}, {"choices", rows}};
    // Per value of each choice parameter, its best combination on the fresh samples, against
    // the best of all: "18 or 36 positions?" with the other choices at their best.
    json by = json::array();
    for (const auto& c : spec.choices) {
      if (c.values.size() < 2) continue;
      json values = json::array();
      for (const auto& val : c.values) {
        std::optional<std::size_t> pick;
        for (std::size_t r = 0; r < out.runs.size(); ++r) {
          if (verified[r].empty() || out.runs[r].choice.at(c.parameter) != val) continue;
          if (!pick || rows[r]["objective"]["value"].get<double>() < rows[*pick]["objective"]["value"].get<double>()) pick = r;
        }
        json j{{"value", val}};
        if (pick) {
          j["run"] = *pick;
          j["choice"] = out.runs[*pick].choice;
          j["objective"] = rows[*pick]["objective"];
          if (rows[*pick].contains("minus_best")) j["minus_best"] = rows[*pick]["minus_best"];
          if (rows[*pick].contains("second")) j["second"] = rows[*pick]["second"];
        }
        values.push_back(j);
      }
      by.push_back({{"parameter", c.parameter}, {"values", values}});
    }
    out.comparison["by_parameter"] = by;
  }
  // The Pareto front: feasible evaluations no other beats on both objectives.
  if (spec.pareto) {
    std::vector<std::size_t> idx;
    for (std::size_t i = 0; i < out.pool.size(); ++i) {
      if (out.pool[i].feasible && std::isfinite(out.pool[i].objective) && std::isfinite(out.pool[i].second)) idx.push_back(i);
    }
    std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) {
      const auto &pa = out.pool[a], &pb = out.pool[b];
      return pa.second != pb.second ? pa.second < pb.second : pa.objective < pb.objective;
    });
    double best_obj = INFINITY;
    for (std::size_t i : idx) {
      if (out.pool[i].objective < best_obj) {
        out.front.push_back(i);
        best_obj = out.pool[i].objective;
      }
    }
    json fv = json::array();
    for (std::size_t i : out.front) {
      const ParetoPoint& p = out.pool[i];
      const studies::StudyEvaluation ef = verify(overrides_of(spec, p.x, out.choices[p.choice]));
      json j{{"choice", out.choices[p.choice]}, {"x", json::object()}, {"objective_optimization", p.objective},
             {"second_optimization", p.second}, {"failures", ef.failures}};
      for (std::size_t q = 0; q < spec.variables.size(); ++q) {
        j["x"][spec.variables[q].parameter] = override_text(p.x[q], spec.variables[q].unit);
      }
      if (!spec.objective_output.empty()) {
        j["objective"] = statistic_with_ci(ef.values[ef.index(spec.objective_output)], spec.objective_statistic,
                                           spec.verification_seed);
      }
      j["second"] = statistic_with_ci(ef.values[ef.index(spec.pareto->output)], spec.pareto->statistic,
                                      spec.verification_seed);
      json cons = json::array();
      for (const auto& c : spec.constraints) {
        cons.push_back({{"output", c.output}, {"statistic", c.statistic},
                        {"value", studies::statistic(ef.values[ef.index(c.output)], c.statistic)}});
      }
      j["constraints"] = cons;
      fv.push_back(j);
    }
    out.front_verification = fv;
  }
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
  // pareto.csv: every evaluation of every search, with both objectives.
  if (spec.pareto) {
    std::ofstream p(fs::path(dir) / "pareto.csv");
    p << "choice,search";
    for (const auto& v : spec.variables) p << ',' << v.parameter << (v.unit.empty() ? "" : "_" + v.unit);
    p << ",objective,second,feasible,on_front\n";
    for (std::size_t i = 0; i < out.pool.size(); ++i) {
      const ParetoPoint& q = out.pool[i];
      p << q.choice << ',' << studies::csv_text(q.search);
      for (double x : q.x) p << ',' << studies::csv_number(x);
      p << ',' << studies::csv_number(q.objective) << ',' << studies::csv_number(q.second) << ',' << (q.feasible ? 1 : 0)
        << ',' << (std::find(out.front.begin(), out.front.end(), i) != out.front.end() ? 1 : 0) << '\n';
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
    if (!out.comparison.is_null()) s["choices_compared"] = out.comparison;
    if (spec.pareto) {
      s["pareto"] = {{"objective", {{"output", spec.objective_output}, {"statistic", spec.objective_statistic}}},
                     {"second", {{"output", spec.pareto->output}, {"statistic", spec.pareto->statistic}}},
                     {"evaluations", out.pool.size()}, {"front", out.front_verification}};
    }
  } else {
    s["message"] = out.message;
  }
  s["provenance"] = {{"poise_version", kVersion}, {"git_commit", studies::git_commit()},
                     {"optimization_file_sha1", studies::file_sha1(spec.file)},
                     {"study_file_sha1", studies::file_sha1(spec.base.file)}, {"threads", threads},
                     {"started", started}, {"finished", studies::now_iso8601()}};
  studies::write_file_atomic((fs::path(dir) / "summary.json").string(), s.dump(2) + "\n");
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
    if (spec.pareto && out.feasible) {
      std::ofstream d2(pdir / "pareto.dat");
      for (const auto& q : out.pool) {
        if (q.feasible) d2 << q.second << ' ' << q.objective << ' ' << q.choice << '\n';
      }
      d2 << "\n\n";
      for (const auto& f : out.front_verification) {
        const json& o = f["objective"];
        const json& sd = f["second"];
        d2 << sd["value"].get<double>() << ' ' << o["value"].get<double>() << ' ' << o.value("lo", o["value"].get<double>())
           << ' ' << o.value("hi", o["value"].get<double>()) << ' ' << f["objective_optimization"].get<double>() << '\n';
      }
      d2.close();
      const std::string xl = spec.pareto->statistic + " of " + spec.pareto->output + " [" +
                             studies::unit_of_output(spec.pareto->output) + "]";
      const std::string yl = spec.objective_statistic + " of " + spec.objective_output + " [" +
                             studies::unit_of_output(spec.objective_output) + "]";
      std::ofstream(pdir / "pareto.gp")
          << "set terminal svg size 760,480 dynamic noenhanced font 'Helvetica,12'\nset output 'pareto.svg'\n"
             "set grid\nset title 'Pareto front'\nset xlabel '" << xl << "'\nset ylabel '" << yl
          << "'\nset key outside bottom center horizontal\n"
             "plot 'pareto.dat' index 0 u 1:2:3 w p pt 7 ps 0.6 lc variable title 'feasible evaluations (colour: choice)', "
             "'pareto.dat' index 1 u 1:5 w lp pt 6 ps 1.2 lc rgb 'black' title 'front (optimization samples)', "
             "'pareto.dat' index 1 u 1:2:3:4 w yerrorbars pt 7 lc rgb 'red' title 'front verified, 95% CI'\n";
      if (studies::run_gnuplot((pdir / "pareto.gp").string(), &why)) figures.push_back("pareto.svg");
    }
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
  auto ci_text = [](const json& e) {
    char buf[160];
    if (e.contains("lo")) {
      std::snprintf(buf, sizeof buf, "%.4g [%.4g, %.4g]", e["value"].get<double>(), e["lo"].get<double>(),
                    e["hi"].get<double>());
    } else {
      std::snprintf(buf, sizeof buf, "%.4g", e["value"].get<double>());
    }
    return std::string(buf);
  };
  // "minus best [95% CI]" and "best ahead" cells of a compared choice ("(best)" for the best).
  auto difference_cells = [&](const json& row) {
    if (!row.contains("minus_best")) return std::string("<td>(best)</td><td></td>");
    const json& d = row["minus_best"];
    json dd{{"value", d["difference"]}};
    if (d.contains("lo")) {
      dd["lo"] = d["lo"];
      dd["hi"] = d["hi"];
    }
    return "<td>" + ci_text(dd) + "</td><td>" +
           (d.contains("share_best_ahead") ? fmt_pct(d["share_best_ahead"].get<double>()) : "") + "</td>";
  };
  if (!out.comparison.is_null()) {
    h << "<h2>Choices compared on fresh random numbers</h2>\n<p>The best design of each choice, run with the same "
      << spec.verification_samples << " fresh samples (seed " << spec.verification_seed << "): " << spec.objective_statistic
      << " of " << studies::html_escape(spec.objective_output) << " with its bootstrap 95% interval, and its difference "
         "from the choice best on these samples (paired bootstrap: same samples; 'best ahead' is the share of resamples "
         "in which that choice stays better). 'picked' marks the optimization's pick, chosen on the optimization "
         "samples.</p>\n<table><tr><th class='l'>choice</th><th>objective [95% CI]</th>"
      << (spec.pareto ? "<th>second objective</th>" : "") << "<th>minus best [95% CI]</th><th>best ahead</th></tr>\n";
    for (const auto& r : out.comparison["choices"]) {
      h << "<tr><td class='l'>" << studies::html_escape(r["choice"].dump()) << (r["best"].get<bool>() ? " (best)" : "")
        << (r["optimization_pick"].get<bool>() ? " (picked)" : "") << "</td>";
      if (!r["feasible"].get<bool>()) {
        h << "<td colspan='4'>no feasible design</td></tr>\n";
        continue;
      }
      h << "<td>" << ci_text(r["objective"]) << "</td>";
      if (spec.pareto) h << "<td>" << ci_text(r["second"]) << "</td>";
      h << difference_cells(r) << "</tr>\n";
    }
    h << "</table>\n";
    for (const auto& p : out.comparison["by_parameter"]) {
      h << "<p><b>" << studies::html_escape(p["parameter"].get<std::string>())
        << "</b>, each value with the other choices at their best:</p>\n<table><tr><th class='l'>value</th>"
           "<th class='l'>best combination</th><th>objective [95% CI]</th>"
        << (spec.pareto ? "<th>second objective</th>" : "") << "<th>minus best [95% CI]</th><th>best ahead</th></tr>\n";
      for (const auto& v : p["values"]) {
        h << "<tr><td class='l'>" << studies::html_escape(v["value"].get<std::string>()) << "</td>";
        if (!v.contains("run")) {
          h << "<td colspan='4'>no feasible design</td></tr>\n";
          continue;
        }
        h << "<td class='l'>" << studies::html_escape(v["choice"].dump()) << "</td><td>" << ci_text(v["objective"]) << "</td>";
        if (spec.pareto) h << "<td>" << ci_text(v["second"]) << "</td>";
        h << difference_cells(v) << "</tr>\n";
      }
      h << "</table>\n";
    }
  }
  if (spec.pareto && out.feasible) {
    h << "<h2>Pareto front</h2>\n<p>" << out.pool.size() << " evaluations (the objective, the second objective, and "
      << spec.pareto->points << " epsilon-constrained searches per choice); the front is the feasible evaluations no "
         "other beats on both. Each front point verified with fresh samples (bootstrap 95% CIs).</p>\n"
         "<table><tr><th class='l'>choice</th><th class='l'>design</th><th>"
      << studies::html_escape(spec.pareto->statistic + " " + spec.pareto->output) << "</th><th>"
      << studies::html_escape(spec.objective_statistic + " " + spec.objective_output) << " (optimization)</th><th>verified [95% CI]</th></tr>\n";
    for (const auto& f : out.front_verification) {
      h << "<tr><td class='l'>" << studies::html_escape(f["choice"].dump()) << "</td><td class='l'>"
        << studies::html_escape(f["x"].dump()) << "</td><td>" << ci_text(f["second"]) << "</td><td>"
        << ci_text(json{{"value", f["objective_optimization"]}}) << "</td><td>" << ci_text(f["objective"]) << "</td></tr>\n";
    }
    h << "</table>\n";
  }
  if (out.feasible) {
    h << "<h2>Optimum, verified with fresh random numbers</h2>\n<pre>" << studies::html_escape(json(out.optimum).dump(2))
      << "</pre>\n<pre>" << studies::html_escape(out.verification.dump(2)) << "</pre>\n";
  } else {
    h << "<h2>No feasible design</h2>\n<p>" << studies::html_escape(out.message) << "</p>\n";
  }
  h << studies::figures_html(pdir, figures);
  if (!spec.notes.empty()) h << "<h2>Notes</h2>\n<pre>" << studies::html_escape(spec.notes) << "</pre>\n";
  h << "</body></html>\n";
  studies::write_file_atomic((fs::path(dir) / "report.html").string(), h.str());
  if (!out.feasible) throw Error(out.message + " (history in " + dir + ")");
  return dir;
}

}  // namespace poise::optimize
