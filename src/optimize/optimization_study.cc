#include "optimize/optimization_study.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/format.h"
#include "engine/kind_interface/procedure_study.h"
#include "optimize/optimization_output.h"
#include "optimize/optimum_neighbourhood.h"
#include "sampling/random_stream.h"
#include "sampling/statistics.h"

namespace poise::optimize {
namespace {
using nlohmann::json;

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

// A design value in words with the digits that tell designs apart: at least 3 significant
// ones, and the decimals of the spread's step where that shows more; never rounded coarser,
// so the sentence says the optimum summary.json holds (6.84 mm, not 7 mm beside a spread of
// 4.94-6.84). Without a spread (step 0): 4 significant digits.
std::string rounded_text(double v, double step, const std::string& unit) {
  std::string text;
  if (step > 0 && std::isfinite(v)) {
    const int magnitude = v != 0.0 ? static_cast<int>(std::floor(std::log10(std::abs(v)))) : 0;
    const int decimals = std::max({0, 2 - magnitude, -static_cast<int>(std::floor(std::log10(step)))});
    text = fixed(v, decimals);
  } else {
    text = significant(v);
  }
  return unit.empty() ? text : text + " " + unit;
}

// The design in words: "yaw.bearing_span 131 mm (127-133 over 3 searches), ...".
std::string design_text(const OptimizationSpec& spec, const std::vector<double>& x, const json& spread) {
  std::string s;
  for (std::size_t i = 0; i < spec.variables.size(); ++i) {
    const auto& v = spec.variables[i];
    double step = 0.0;
    std::string range;
    if (spread.is_object() && spread.contains("variables")) {
      const json& sv = spread["variables"][i];
      step = sv["supported_step"].get<double>();
      range = " (" + short_number(sv["min"].get<double>()) + "-" + short_number(sv["max"].get<double>()) + " over " +
              std::to_string(spread["searches"].get<int>()) + " searches)";
    }
    s += (s.empty() ? "" : ", ") + v.parameter + " " + rounded_text(x[i], step, v.unit) + range;
  }
  return s;
}

/// The searches, one per combination of the choices, on the search's own samples.
void run_searches(const OptimizationSpec& spec, OptimizationOutcome& out, int threads, RunProgress& progress) {
  double best_f = INFINITY;
  for (std::size_t ci = 0; ci < out.choices.size(); ++ci) {
    SearchSetup setup;
    setup.choice_index = ci;
    setup.seed = spec.seed;
    setup.pareto = spec.pareto.has_value();
    setup.pool = spec.pareto ? &out.pool : nullptr;
    setup.label = choice_label(out.choices[ci]);
    ChoiceResult cr = search_choice(spec, out.choices[ci], setup, threads, progress);
    if (cr.result.feasible && cr.result.best.objective < best_f) {
      best_f = cr.result.best.objective;
      out.optimization_pick = out.runs.size();
      out.feasible = true;
    }
    out.runs.push_back(std::move(cr));
  }
}

/// No design met the constraints: how far the closest came, in the message and the answer.
void explain_no_design(const OptimizationSpec& spec, OptimizationOutcome& out) {
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
        closest = spec.constraints[which].describe() + " missed by " + value_text(worst, "");
      }
    }
  }
  std::string failed;
  for (const auto& run : out.runs) {
    for (const auto& h : run.result.history) {
      if (!h.result.ok && failed.empty()) failed = h.result.message;
    }
  }
  out.message = "no design met the constraints in " + std::to_string(spec.max_evaluations) + " evaluations per choice" +
                (closest.empty() ? "" : "; closest: " + closest) +
                (failed.empty() ? "" : "; a failed evaluation: " + failed) +
                ". Relax a constraint, widen the bounds or change the algorithm (a global one: direct_l, isres).";
  out.answer = "No design found: " + out.message;
}

/// The choices decided on fresh samples, or the single optimum checked.
void decide_or_check(const OptimizationSpec& spec, OptimizationOutcome& out, int threads, RunProgress& progress) {
  if (out.choices.size() > 1) {
    const ChoiceDecision d = decide_choices(spec, out.runs, out.optimization_pick, threads, progress);
    out.best = d.headline;
    out.comparison = d.json;
    for (const auto& c : d.fresh) {
      if (c.run == d.headline) out.check = c.comparison;
    }
    out.answer = d.sentence;
  } else {
    out.best = 0;
    const auto e = engine::evaluate_study(spec.base, overrides_of(spec, out.runs[0].result.x, out.runs[0].choice),
                                          spec.verification_samples, spec.verification_seed, threads);
    out.check = check_design(spec, out.runs[0].result.x, e, spec.verification_seed);
    progress.step(static_cast<double>(spec.verification_samples),
                  "[check] " + std::to_string(spec.verification_samples) + " fresh samples: constraints " +
                      to_string(out.check.verdict));
  }
}

/// search_model = "fast": the headline design on its own fresh samples under the fast model as
/// well, so the answer says how far the model the searches ran is from the full one there.
void measure_fast_model_gap(const OptimizationSpec& spec, OptimizationOutcome& out, const ChoiceResult& best,
                            int threads, RunProgress& progress) {
  if (!spec.fast_search) return;
  const auto e = engine::evaluate_study(spec.search_study(), out.optimum, out.check.samples, out.check.seed, threads);
  const FreshCheck fast = check_design(spec, best.result.x, e, out.check.seed);
  progress.step(static_cast<double>(out.check.samples), "[fast model] the same fresh samples on the fast model", true);
  auto pair = [](double full, double quick) {
    const double d = quick - full;
    return json{
        {"full", full}, {"fast", quick}, {"difference", d}, {"relative", full != 0.0 ? d / std::fabs(full) : 0.0}};
  };
  json j{{"description", spec.fast_model_text},
         {"samples", out.check.samples},
         {"seed", out.check.seed},
         {"objective", pair(out.check.objective_value, fast.objective_value)}};
  double largest_sample = 0.0;  // the objective output, sample by sample
  if (out.check.objective_values.size() == fast.objective_values.size() && out.check.ok_index == fast.ok_index) {
    for (std::size_t i = 0; i < fast.objective_values.size(); ++i) {
      largest_sample = std::max(largest_sample, std::fabs(fast.objective_values[i] - out.check.objective_values[i]));
    }
    j["objective_output_largest_sample_difference"] = largest_sample;
  }
  json cons = json::array();
  bool same = fast.verdict == out.check.verdict;
  for (std::size_t k = 0; k < out.check.constraints.size() && k < fast.constraints.size(); ++k) {
    const auto &cf = out.check.constraints[k], &cq = fast.constraints[k];
    json c = pair(cf.bound ? *cf.bound : cf.interval.value, cq.bound ? *cq.bound : cq.interval.value);
    c["name"] = cf.requirement.name;
    c["same_verdict"] = cf.verdict == cq.verdict;
    same = same && cf.verdict == cq.verdict;
    cons.push_back(c);
  }
  j["constraints"] = cons;
  j["same_verdicts"] = same;
  out.fast_model = j;
}

/// The Pareto front: feasible evaluations no other beats on both objectives, each checked on
/// the comparison set.
void pareto_front(const OptimizationSpec& spec, OptimizationOutcome& out, int threads, RunProgress& progress) {
  if (spec.pareto) {
    std::vector<std::size_t> idx;
    for (std::size_t i = 0; i < out.pool.size(); ++i) {
      if (out.pool[i].feasible && std::isfinite(out.pool[i].objective) && std::isfinite(out.pool[i].second))
        idx.push_back(i);
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
    progress.plan(static_cast<double>(out.front.size() * spec.verification_samples));
    json fv = json::array();
    for (std::size_t i : out.front) {
      const ParetoPoint& p = out.pool[i];
      // With a fast search the front is drawn on the fast model, fresh samples too: it informs,
      // the headline's check on the full model decides (and states the gap between the two).
      const auto ef = engine::evaluate_study(spec.search_study(), overrides_of(spec, p.x, out.choices[p.choice]),
                                             spec.verification_samples, spec.verification_seed, threads);
      const FreshCheck f = check_design(spec, p.x, ef, spec.verification_seed);
      progress.step(
          static_cast<double>(spec.verification_samples),
          std::string("[pareto front] point checked on fresh samples") + (spec.fast_search ? " (fast model)" : ""),
          spec.fast_search);
      json j{{"choice", out.choices[p.choice]},
             {"label", choice_label(out.choices[p.choice])},
             {"x", json::object()},
             {"model", spec.fast_search ? "fast" : "full"},
             {"objective_optimization", p.objective},
             {"second_optimization", p.second},
             {"failures", f.failures},
             {"constraints_verdict", to_string(f.verdict)}};
      for (std::size_t q = 0; q < spec.variables.size(); ++q) {
        j["x"][spec.variables[q].parameter] = value_text(p.x[q], spec.variables[q].unit);
      }
      j["objective"] = f.objective ? interval_json(*f.objective) : json{{"value", f.objective_value}};
      if (f.second) j["second"] = interval_json(*f.second);
      fv.push_back(j);
    }
    out.front_verification = fv;
  }
}

/// The answer in one sentence: the decision, the design and its fresh-sample verdict.
void answer_sentence(const OptimizationSpec& spec, OptimizationOutcome& out, const ChoiceResult& best) {
  {
    std::string s = out.answer;
    const std::string design = design_text(spec, best.result.x, out.spread);
    std::string objective;
    if (!spec.objective_output.empty() && out.check.objective) {
      objective = spec.objective_statistic + " of " + spec.objective_output + " " +
                  interval_text(*out.check.objective, output_unit(spec, spec.objective_output));
    } else {
      objective =
          "sum " +
          rounded_text(out.check.objective_value,
                       out.spread.contains("objective") ? out.spread["objective"]["supported_step"].get<double>() : 0.0,
                       spec.variables[0].unit);
    }
    // The choice sentence names the headline combination already.
    const std::string label = choice_label(best.choice);
    const bool named = s.rfind(label, 0) == 0;
    const std::string head = (out.runs.size() > 1 && !named ? label + ", " : std::string()) + design;
    std::string check = "on " + std::to_string(out.check.samples) + " fresh samples ";
    if (out.verified && out.check.constraints.size() > 1) {
      // Said in short: each constraint's figure is in the report's and summary.json's table.
      check = "verified on " + std::to_string(out.check.samples) + " fresh samples (all " +
              std::to_string(out.check.constraints.size()) + " constraints pass)";
    } else if (out.verified) {
      std::string cons;
      for (std::size_t k = 0; k < out.check.constraints.size(); ++k)
        cons += (k ? "; " : "") + out.check.describe_constraint(k);
      check += cons.empty() ? "it is verified" : cons + ": verified";
    } else {
      check += "it is NOT verified: " + out.check.problems();
      if (out.nearest.value("found", false)) {
        const std::vector<double> xn = out.nearest["x"].get<std::vector<double>>();
        std::string cons;
        for (const auto& c : out.nearest["recheck"]["constraints"]) {
          cons += (cons.empty() ? "" : "; ") + c["text"].get<std::string>();
        }
        check += "; nearest design that passes: " + design_text(spec, xn, json()) + " (" + cons + ", re-verified on " +
                 std::to_string(spec.verification_samples) + " other fresh samples)";
      } else {
        check += "; no nearby design that passes was found (" + out.nearest.value("why", std::string()) + ")";
      }
    }
    // A decision among choices has stated the objective's figures already.
    const bool decided = out.runs.size() > 1 && !spec.objective_output.empty() && !s.empty();
    const std::string design_part = "design: " + head + (decided ? "" : ", " + objective) + "; " + check;
    out.answer = s.empty() ? "Optimum " + design_part : s + "; " + design_part;
  }
}

void count_cost(const RunProgress& progress, OptimizationOutcome& out) {
  out.design_evaluations = progress.evaluations();
  out.model_samples = static_cast<std::size_t>(progress.full_samples());
  out.fast_evaluations = progress.fast_evaluations();
  out.fast_samples = static_cast<std::size_t>(progress.fast_samples());
}

// ", which on the headline's 256 fresh samples gives p95 of x 4.16 % against 4.16 % of the
// full model (relative difference 1e-5; the same constraint verdicts)".
std::string fast_model_clause(const OptimizationSpec& spec, const OptimizationOutcome& out) {
  if (!out.fast_model.is_object() || !out.fast_model.contains("objective")) return "";
  const json& o = out.fast_model["objective"];
  const std::string unit = spec.objective_output.empty() ? std::string() : output_unit(spec, spec.objective_output);
  const std::string what =
      spec.objective_output.empty() ? "the objective" : spec.objective_statistic + " of " + spec.objective_output;
  const std::string rel = fmt::format("{:.1e}", std::fabs(o["relative"].get<double>()));
  return ", which on the headline's " + std::to_string(out.fast_model["samples"].get<std::size_t>()) +
         " fresh samples gives " + what + " " +
         poise::interval_text(o["fast"].get<double>(), std::nullopt, std::nullopt).value + " against " +
         poise::interval_text(o["full"].get<double>(), std::nullopt, std::nullopt).value +
         (unit.empty() ? "" : " " + unit) + " of the full model (relative difference " + rel + "; " +
         (out.fast_model["same_verdicts"].get<bool>() ? "the same constraint verdicts"
                                                      : "constraint verdicts that DIFFER: the full model decides") +
         ")";
}

}  // namespace

nlohmann::json statistic_with_ci(const std::vector<double>& values, const std::string& stat, std::uint64_t seed,
                                 int resamples) {
  json j{{"value", engine::statistic(values, stat)}};
  if (values.size() < 2) return j;
  sampling::RandomStream rs(seed, sampling::StreamId::kBootstrap, 0);
  std::vector<double> boot(static_cast<std::size_t>(resamples)), r(values.size());
  for (auto& b : boot) {
    for (auto& v : r) v = values[static_cast<std::size_t>(rs.uniform() * static_cast<double>(values.size()))];
    b = engine::statistic(r, stat);
  }
  std::sort(boot.begin(), boot.end());
  j["lo"] = sampling::quantile_sorted(boot, 0.025).value;
  j["hi"] = sampling::quantile_sorted(boot, 0.975).value;
  return j;
}

OptimizationOutcome optimize(const OptimizationSpec& spec, int threads, bool progress_on) {
  OptimizationOutcome out;
  RunProgress progress(progress_on);
  out.choices = combinations(spec.choices);
  const bool several = out.choices.size() > 1;
  // The plan: the searches, the fresh sets (selection, comparison or check), the replicates
  // and one evaluation on the search's samples; the nearest-design rounds are added if needed.
  progress.plan(static_cast<double>(out.choices.size()) * planned_search_samples(spec, true));
  progress.plan(static_cast<double>((spec.replicates - 1)) * planned_search_samples(spec, false));
  progress.plan(static_cast<double>(spec.samples));
  if (!several) progress.plan(static_cast<double>(spec.verification_samples));
  run_searches(spec, out, threads, progress);
  if (!out.feasible) {
    explain_no_design(spec, out);
    count_cost(progress, out);
    return out;
  }
  // Then: the decision or the check, the spread, the constraints at the optimum, the nearest
  // passing design when needed, the front and the answer.
  decide_or_check(spec, out, threads, progress);
  const ChoiceResult& best = out.runs[out.best];
  out.optimum = overrides_of(spec, best.result.x, best.choice);
  measure_fast_model_gap(spec, out, best, threads, progress);
  out.verified = out.check.verdict == Verdict::kPasses;
  out.verification = out.check.to_json();
  measure_spread(spec, out, best, threads, progress);
  constraints_at_optimum(spec, out, best, threads, progress);
  find_nearest_design(spec, out, best, threads, progress);
  pareto_front(spec, out, threads, progress);
  answer_sentence(spec, out, best);
  count_cost(progress, out);
  // What it cost, in the answer: the planner sees what another question would take.
  const bool closed = !out.answer.empty() && out.answer.back() == '.';
  if (closed) out.answer.pop_back();
  if (out.fast_evaluations > 0) {
    out.answer += "; the searches ran the fast model (" + std::to_string(out.fast_evaluations) +
                  " design evaluations, " + std::to_string(out.fast_samples) + " samples)" +
                  fast_model_clause(spec, out) + "; the full model ran " +
                  std::to_string(out.design_evaluations - out.fast_evaluations) + " design evaluations (" +
                  std::to_string(out.model_samples) + " samples).";
  } else {
    out.answer += "; it took " + std::to_string(out.design_evaluations) + " design evaluations (" +
                  std::to_string(out.model_samples) + " samples of the full model).";
  }
  return out;
}

OptimizationRun run_optimization(const std::string& path, const engine::RunOptions& options,
                                 std::optional<std::uint64_t> seed) {
  OptimizationSpec spec = load_optimization(path);
  if (seed) spec.seed = *seed;
  return write_optimization(spec, options);
}

}  // namespace poise::optimize
