#include "optimize/optimum_neighbourhood.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "engine/kind_interface/procedure_study.h"
#include "optimize/optimization_output.h"
#include "sampling/random_stream.h"
#include "sampling/statistics.h"

namespace poise::optimize {
namespace {
using nlohmann::json;

// The step a spread supports: the power of ten at or below the range (0: no spread seen).
double supported_step(double range) { return range > 0 ? std::pow(10.0, std::floor(std::log10(range))) : 0.0; }

}  // namespace

/// The optimum's own uncertainty: the search repeated with independent seeds.
void measure_spread(const OptimizationSpec& spec, OptimizationOutcome& out, const ChoiceResult& best, int threads,
                    RunProgress& progress) {
  {
    json vars = json::array();
    std::vector<std::vector<double>> xs{best.result.x};
    std::vector<double> fs{best.result.best.objective};
    json searches = json::array(
        {{{"seed", spec.seed}, {"feasible", true}, {"x", best.result.x}, {"objective", best.result.best.objective}}});
    for (int r = 1; r < spec.replicates; ++r) {
      SearchSetup setup;
      setup.seed = spec.replicate_seed(r);
      setup.label = "replicate " + std::to_string(r + 1) + " of " + std::to_string(spec.replicates) + ", seed " +
                    std::to_string(setup.seed);
      const ChoiceResult rr = search_choice(spec, best.choice, setup, threads, progress);
      json sj{{"seed", setup.seed}, {"feasible", rr.result.feasible}};
      if (rr.result.feasible) {
        xs.push_back(rr.result.x);
        fs.push_back(rr.result.best.objective);
        sj["x"] = rr.result.x;
        sj["objective"] = rr.result.best.objective;
      }
      searches.push_back(sj);
    }
    auto spread_of = [](const std::vector<double>& v) {
      const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
      double m = 0.0, s = 0.0;
      for (double x : v) m += x / static_cast<double>(v.size());
      for (double x : v) s += (x - m) * (x - m);
      return json{{"min", *lo},
                  {"max", *hi},
                  {"mean", m},
                  {"std", v.size() > 1 ? std::sqrt(s / static_cast<double>(v.size() - 1)) : 0.0},
                  {"supported_step", supported_step(*hi - *lo)}};
    };
    for (std::size_t i = 0; i < spec.variables.size(); ++i) {
      std::vector<double> v;
      v.reserve(xs.size());
      for (const auto& x : xs) v.push_back(x[i]);
      json j = spread_of(v);
      j["parameter"] = spec.variables[i].parameter;
      j["unit"] = spec.variables[i].unit;
      vars.push_back(j);
    }
    out.spread = {{"searches", static_cast<int>(xs.size())},
                  {"requested", spec.replicates},
                  {"variables", vars},
                  {"objective", spread_of(fs)},
                  {"runs", searches}};
    if (spec.replicates < 2) out.spread = json{{"searches", 1}, {"requested", 1}};
  }
}

/// Each constraint at the optimum on the search's own samples, with its interval.
void constraints_at_optimum(const OptimizationSpec& spec, OptimizationOutcome& out, const ChoiceResult& best,
                            int threads, RunProgress& progress) {
  {
    const auto e = engine::evaluate_study(spec.search_study(), out.optimum, spec.samples, spec.seed, threads);
    const FreshCheck own = check_design(spec, best.result.x, e, spec.seed);
    progress.step(static_cast<double>(spec.samples), "[optimum] constraints on the search's own samples",
                  spec.fast_search);
    json b = json::array();
    for (std::size_t k = 0; k < own.constraints.size(); ++k) {
      const auto& c = own.constraints[k];
      const double figure = c.bound ? *c.bound : c.interval.value;
      const double scale = std::max(std::fabs(c.requirement.limit()), 1e-12);
      json j{{"name", c.requirement.name},
             {"interval", interval_json(c.interval)},
             {"figure", figure},
             {"limit", c.requirement.limit()},
             {"binding", std::fabs(figure - c.requirement.limit()) <= 0.02 * scale},
             {"text", own.describe_constraint(k)}};
      b.push_back(j);
    }
    out.binding = b;
  }
}

namespace {

// Each constraint the last check did not pass, tightened by its excess over the limit (at the
// interval's far end) plus 1% of the limit.
void tighten_failed_limits(const OptimizationSpec& spec, const FreshCheck& last, OptimizationSpec& tight) {
  for (std::size_t k = 0; k < tight.constraints.size(); ++k) {
    const ConstraintCheck& c = last.constraints[k];
    if (c.verdict == Verdict::kPasses) continue;
    Requirement& r = tight.constraints[k];
    const Requirement& orig = spec.constraints[k];
    const bool upper = r.at_most.has_value();
    const std::optional<double> far = c.bound ? c.bound : (upper ? c.interval.hi : c.interval.lo);
    const double end = far ? *far : c.interval.value;
    double excess = upper ? end - orig.limit() : orig.limit() - end;
    excess = std::max(excess, 0.0) + 0.01 * std::max(std::fabs(orig.limit()), 1e-12);
    if (upper) {
      *r.at_most -= excess;
    } else {
      *r.at_least += excess;
    }
  }
}

// A design that passed its check, checked again on the re-check's fresh samples; true (and
// out.nearest set) when it passes there too.
bool recheck_nearest(const OptimizationSpec& spec, OptimizationOutcome& out, const ChoiceResult& best,
                     const std::vector<double>& x, int round, int threads, RunProgress& progress, FreshCheck& last,
                     json& rj, json& rounds) {
  const auto design = overrides_of(spec, x, best.choice);
  const auto e2 = engine::evaluate_study(spec.base, design, spec.verification_samples, spec.recheck_seed(), threads);
  const FreshCheck again = check_design(spec, x, e2, spec.recheck_seed());
  progress.step(static_cast<double>(spec.verification_samples),
                "[nearest, round " + std::to_string(round) + "] re-check: " + to_string(again.verdict));
  rj["recheck"] = again.to_json();
  if (again.verdict != Verdict::kPasses) {
    last = again;
    return false;
  }
  rounds.push_back(rj);
  json design_json;
  for (std::size_t i = 0; i < spec.variables.size(); ++i) {
    design_json[spec.variables[i].parameter] = value_text(x[i], spec.variables[i].unit);
  }
  out.nearest = {{"found", true},
                 {"design", design_json},
                 {"overrides", design},
                 {"x", x},
                 {"objective", again.objective_value},
                 {"check", last.to_json()},
                 {"recheck", again.to_json()},
                 {"rounds", rounds}};
  return true;
}

}  // namespace

/// Not verified: the nearest design that passes, by tightening what failed by its excess.
void find_nearest_design(const OptimizationSpec& spec, OptimizationOutcome& out, const ChoiceResult& best, int threads,
                         RunProgress& progress) {
  if (out.verified) return;
  json rounds = json::array();
  OptimizationSpec tight = spec;
  FreshCheck last = out.check;
  std::vector<double> x = best.result.x;
  std::string why_none;
  if (!last.failures_ok) why_none = "its samples fail beyond max_failure_share, which tighter limits do not cure";
  for (int round = 1; round <= spec.max_nearest_rounds && why_none.empty(); ++round) {
    progress.plan(planned_search_samples(spec, false) + 2.0 * static_cast<double>(spec.verification_samples));
    tighten_failed_limits(spec, last, tight);
    SearchSetup setup;
    setup.seed = spec.seed;
    setup.start = x;
    setup.label = "nearest, round " + std::to_string(round);
    const ChoiceResult nr = search_choice(tight, best.choice, setup, threads, progress);
    json rj{{"round", round}};
    json limits = json::array();
    for (const auto& r : tight.constraints) limits.push_back({{"name", r.name}, {"limit", r.limit()}});
    rj["tightened_limits"] = limits;
    if (!nr.result.feasible) {
      rj["feasible"] = false;
      rounds.push_back(rj);
      why_none = "no design met the tightened limits (round " + std::to_string(round) + ")";
      break;
    }
    x = nr.result.x;
    const auto design = overrides_of(spec, x, best.choice);
    const auto e =
        engine::evaluate_study(spec.base, design, spec.verification_samples, spec.verification_seed, threads);
    last = check_design(spec, x, e, spec.verification_seed);
    progress.step(static_cast<double>(spec.verification_samples),
                  "[nearest, round " + std::to_string(round) + "] check: " + to_string(last.verdict));
    rj["x"] = x;
    rj["objective"] = nr.result.best.objective;
    rj["check"] = last.to_json();
    if (last.verdict == Verdict::kPasses &&
        recheck_nearest(spec, out, best, x, round, threads, progress, last, rj, rounds)) {
      break;
    }
    rounds.push_back(rj);
  }
  if (out.nearest.is_null()) {
    if (why_none.empty()) why_none = "none passed in " + std::to_string(spec.max_nearest_rounds) + " tightening rounds";
    out.nearest = {{"found", false}, {"why", why_none}, {"rounds", rounds}};
  }
}

}  // namespace poise::optimize
