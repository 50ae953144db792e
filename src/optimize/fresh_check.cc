#include "optimize/fresh_check.h"

#include <cmath>

#include "core/format.h"
#include "engine/kind_interface/procedure_study.h"
#include "optimize/design_search.h"

namespace poise::optimize {
nlohmann::json interval_json(const Interval& i) {
  nlohmann::json j{{"value", i.value}, {"method", i.method}};
  if (i.lo) j["lo"] = *i.lo;  // a missing end does not exist with these samples
  if (i.hi) j["hi"] = *i.hi;
  return j;
}

std::string output_unit(const OptimizationSpec& spec, const std::string& output) {
  const auto it = spec.output_units.find(output);
  return it == spec.output_units.end() || it->second == "1" ? "" : it->second;
}

std::string to_string(Verdict v) {
  switch (v) {
    case Verdict::kPasses: return "passes";
    case Verdict::kStraddles: return "straddles the limit";
    case Verdict::kFails: return "fails";
  }
  return "?";
}

std::string interval_text(const Interval& i, const std::string& unit) {
  // The digits the interval supports (core/number_text.h), as every report writes them.
  const poise::IntervalText t = poise::interval_text(i.value, i.lo, i.hi);
  std::string s = t.value;
  if (i.lo || i.hi) s += " [" + (i.lo ? t.lo : "?") + ", " + (i.hi ? t.hi : "?") + "]";
  return unit.empty() ? s : s + " " + unit;
}

FreshCheck check_design(const OptimizationSpec& spec, const std::vector<double>& x, const engine::McResult& e,
                        std::uint64_t seed) {
  FreshCheck f;
  f.samples = e.n;
  f.failures = e.failures;
  f.seed = seed;
  f.ok_index = e.ok_index;
  f.failure_share = e.n > 0 ? static_cast<double>(e.failures) / static_cast<double>(e.n) : 0.0;
  f.failures_ok = f.failure_share <= spec.max_failure_share();
  f.verdict = f.failures_ok ? Verdict::kPasses : Verdict::kFails;
  f.stated_met = f.failures_ok;
  auto set_of = [&](const std::string& output) {
    return sample_set(e.values[e.index(output)], e.ok_index, e.replicate_size);
  };
  const bool any = !e.values.empty() && !e.values[0].empty();
  if (!any) {
    f.verdict = Verdict::kFails;
    f.stated_met = false;
    return f;
  }
  if (!spec.objective_output.empty()) {
    f.objective = interval(set_of(spec.objective_output), spec.objective_statistic);
    f.objective_values = e.values[e.index(spec.objective_output)];
  }
  f.objective_value = objective_value(spec, x, e);
  if (spec.pareto) f.second = interval(set_of(spec.pareto->output), spec.pareto->statistic);
  for (const auto& r : spec.constraints) {
    ConstraintCheck c;
    c.requirement = r;
    c.unit = output_unit(spec, r.output);
    const SampleSet s = set_of(r.output);
    c.interval = interval(s, r.statistic);
    auto meets = [&](double v) { return r.at_least ? v >= *r.at_least : v <= *r.at_most; };
    const bool point_met = meets(c.interval.value);
    std::optional<double> far;  // the pessimistic end that must meet the limit
    if (r.bound.side != BoundSide::kNone) {
      c.bound = one_sided_bound(s, r.statistic, r.bound);
      far = c.bound;
      c.stated_met = c.bound && meets(*c.bound);
    } else {
      far = r.at_least ? c.interval.lo : c.interval.hi;
      if (r.statistic == "min" || r.statistic == "max") far = c.interval.value;
      c.stated_met = point_met;
    }
    c.verdict = !point_met ? Verdict::kFails : (far && meets(*far)) ? Verdict::kPasses : Verdict::kStraddles;
    f.verdict = std::max(f.verdict, c.verdict);
    f.stated_met = f.stated_met && c.stated_met;
    f.constraints.push_back(c);
  }
  return f;
}

std::string FreshCheck::describe_constraint(std::size_t k) const {
  const ConstraintCheck& c = constraints[k];
  const Requirement& r = c.requirement;
  const std::string& unit = c.unit;
  std::string s = r.statistic + " of " + r.output + " " + interval_text(c.interval, unit);
  if (c.bound) {
    // One digit more than the interval: it sits by the limit.
    s += " (" + describe(r.bound) + " " + significant(*c.bound) + ")";
  }
  return s + " " + to_string(c.verdict) + " " + (r.at_least ? ">= " : "<= ") + value_text(r.limit(), "") +
         (unit.empty() ? "" : " " + unit);
}

std::string FreshCheck::problems() const {
  std::string s;
  if (!failures_ok) {
    s = fmt::format("{} of {} samples failed ({:.1f}%)", failures, samples, 100.0 * failure_share);
  }
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    if (constraints[k].verdict != Verdict::kPasses) s += (s.empty() ? "" : "; ") + describe_constraint(k);
  }
  return s;
}

nlohmann::json FreshCheck::to_json() const {
  nlohmann::json j{{"samples", samples},
                   {"seed", seed},
                   {"failures", failures},
                   {"failure_share", failure_share},
                   {"failures_within_max_share", failures_ok},
                   {"verdict", to_string(verdict)},
                   {"verified", verdict == Verdict::kPasses},
                   {"constraints_met_as_stated", stated_met}};
  if (objective) j["objective"] = interval_json(*objective);
  j["objective_value"] = objective_value;
  if (second) j["second_objective"] = interval_json(*second);
  nlohmann::json cons = nlohmann::json::array();
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    const ConstraintCheck& c = constraints[k];
    nlohmann::json cj{{"name", c.requirement.name},
                      {"output", c.requirement.output},
                      {"statistic", c.requirement.statistic},
                      {"bound", to_string(c.requirement.bound)},
                      {"limit", c.requirement.limit()},
                      {"at_least", c.requirement.at_least.has_value()},
                      {"interval", interval_json(c.interval)},
                      {"verdict", to_string(c.verdict)},
                      {"text", describe_constraint(k)}};
    if (c.bound) cj["bound_value"] = *c.bound;
    cons.push_back(cj);
  }
  j["constraints"] = cons;
  return j;
}

}  // namespace poise::optimize
