#include "optimize/design_search.h"
#include "core/diagnostics.h"

#include <algorithm>
#include <cmath>

#include "core/format.h"
#include "engine/results/confidence_bound.h"

namespace poise::optimize {

void RunProgress::step(double samples, const std::string& line, bool fast) {
  done_ += samples;
  ++evaluations_;
  if (fast) {
    fast_samples_ += samples;
    ++fast_evaluations_;
  }
  if (!on_) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  // Searches usually converge before their budget, so the plan (and the ETA) is an upper bound.
  const double eta = done_ > 0 ? elapsed / done_ * std::max(planned_ - done_, 0.0) : 0.0;
  diagnostics::progress("  " + line + fmt::format("  ({:.0f} s, ETA <= {:.1f} min)", elapsed, eta / 60.0));
}

double objective_value(const OptimizationSpec& spec, const std::vector<double>& x, const engine::McResult& e) {
  if (!spec.objective_output.empty()) {
    return engine::statistic(e.values[e.index(spec.objective_output)], spec.objective_statistic);
  }
  double f = 0.0;
  for (std::size_t i = 0; i < spec.variables.size(); ++i) {
    if (std::find(spec.variable_sum.begin(), spec.variable_sum.end(), spec.variables[i].parameter) !=
        spec.variable_sum.end()) {
      f += x[i];
    }
  }
  return f;
}

double constraint_figure(const Requirement& r, double c) { return r.at_least ? *r.at_least - c : c + *r.at_most; }

ScoredDesign score_design(const OptimizationSpec& spec, const std::vector<double>& x, const engine::McResult& e) {
  ScoredDesign s;
  s.failure_share = e.n > 0 ? static_cast<double>(e.failures) / static_cast<double>(e.n) : 0.0;
  Evaluation& r = s.primary;
  if (s.failure_share > spec.max_failure_share()) {
    r.ok = false;
    r.message =
        fmt::format("{} of {} samples failed ({:.1f}%, over the study's max_failure_share {:.3g}): ", e.failures, e.n,
                    100.0 * s.failure_share, spec.max_failure_share()) +
        e.first_failure();
    return s;
  }
  r.objective = objective_value(spec, x, e);
  for (const auto& c : spec.constraints) {
    const std::size_t k = e.index(c.output);
    const auto figure = one_sided_bound(sample_set(e.values[k], e.ok_index, e.replicate_size), c.statistic, c.bound);
    if (!figure) {
      r.ok = false;
      r.message = "no " + describe(c.bound) + " of " + c.statistic + " of " + c.output + " from " +
                  std::to_string(e.values[k].size()) + " samples (more samples or replicates needed)";
      r.constraints.clear();
      return s;
    }
    r.constraints.push_back(c.at_least ? *c.at_least - *figure : *figure - *c.at_most);
  }
  if (spec.pareto) s.second = engine::statistic(e.values[e.index(spec.pareto->output)], spec.pareto->statistic);
  return s;
}

std::map<std::string, std::string> overrides_of(const OptimizationSpec& spec, const std::vector<double>& x,
                                                const std::map<std::string, std::string>& choice) {
  std::map<std::string, std::string> o = spec.overrides;
  for (const auto& [k, v] : choice) o[k] = v;
  for (std::size_t i = 0; i < spec.variables.size(); ++i)
    o[spec.variables[i].parameter] = value_text(x[i], spec.variables[i].unit);
  return o;
}

ChoiceResult search_choice(const OptimizationSpec& spec, const std::map<std::string, std::string>& choice,
                           const SearchSetup& setup, int threads, RunProgress& progress) {
  ChoiceResult cr;
  cr.choice = choice;
  cr.seed = setup.seed;
  std::vector<Variable> vars;
  for (std::size_t i = 0; i < spec.variables.size(); ++i) {
    const auto& v = spec.variables[i];
    vars.push_back({v.parameter, v.lower, v.upper, setup.start.empty() ? v.start : setup.start[i]});
  }
  Options opt;
  opt.algorithm = spec.algorithm;
  opt.max_evaluations = spec.max_evaluations;
  opt.xtol_rel = spec.xtol_rel;
  opt.constraints = spec.constraints.size();
  opt.seed = setup.seed;
  int count = 0;
  std::string label;  // the search running
  auto evaluate = [&](const std::vector<double>& x) -> const ScoredDesign& {
    if (auto it = cr.designs.find(x); it != cr.designs.end()) return it->second;
    ScoredDesign sc;
    try {
      const engine::McResult e =
          engine::evaluate_study(spec.search_study(), overrides_of(spec, x, choice), spec.samples, setup.seed, threads);
      sc = score_design(spec, x, e);
    } catch (const std::exception& ex) {
      sc.primary.ok = false;
      sc.primary.message = ex.what();
    }
    ++count;
    if (setup.pool && sc.primary.ok) {
      ParetoPoint p{setup.choice_index, label, x, sc.primary.objective, sc.second, true};
      for (double c : sc.primary.constraints) p.feasible = p.feasible && c <= opt.constraint_tolerance;
      setup.pool->push_back(std::move(p));
    }
    std::string xs;
    for (std::size_t i = 0; i < x.size(); ++i) xs += (i ? ", " : "") + value_text(x[i], spec.variables[i].unit);
    bool feasible = sc.primary.ok;
    for (double c : sc.primary.constraints) feasible = feasible && c <= 0.0;
    progress.step(static_cast<double>(spec.samples),
                  "[" + setup.label + "] evaluation " + std::to_string(count) + ": " + xs + " -> " +
                      (sc.primary.ok ? value_text(sc.primary.objective, "") : sc.primary.message) +
                      (setup.pareto && sc.primary.ok ? ", " + value_text(sc.second, "") : "") +
                      (sc.primary.ok && !feasible ? " (infeasible)" : ""),
                  spec.fast_search);
    return cr.designs.emplace(x, std::move(sc)).first->second;
  };
  // A search: `what` = objective, second, or the objective with second <= level.
  auto search = [&](const std::string& what, double level, const std::vector<double>& start) {
    std::vector<Variable> v = vars;
    for (std::size_t i = 0; i < v.size(); ++i) v[i].start = start[i];
    Options o = opt;
    if (what == "epsilon") o.constraints += 1;
    const Problem f = [&](const std::vector<double>& x) {
      const ScoredDesign& sc = evaluate(x);
      Evaluation r = sc.primary;
      if (!r.ok) return r;
      if (what == "second") r.objective = sc.second;
      if (what == "epsilon") r.constraints.push_back(sc.second - level);
      return r;
    };
    label = what == "epsilon" ? "epsilon " + value_text(level, "") : what;
    return minimize(f, v, o);
  };
  std::vector<double> x0;
  x0.reserve(vars.size());
  for (const auto& v : vars) x0.push_back(v.start);
  cr.result = search("objective", 0.0, x0);
  if (setup.pareto && spec.pareto && cr.result.feasible) {
    const Result second = search("second", 0.0, x0);
    if (second.feasible) {
      const double lo = evaluate(second.x).second, hi = evaluate(cr.result.x).second;
      for (int k = 1; k <= spec.pareto->points && hi > lo; ++k) {
        search("epsilon", lo + (hi - lo) * k / (spec.pareto->points + 1), second.x);
      }
    }
  }
  return cr;
}

double planned_search_samples(const OptimizationSpec& spec, bool pareto) {
  return static_cast<double>(spec.max_evaluations) * static_cast<double>(spec.samples) *
         (pareto && spec.pareto ? 2.0 + spec.pareto->points : 1.0);
}

}  // namespace poise::optimize
