#include "optimize/choice_decision.h"

#include <algorithm>
#include <cmath>

#include "core/format.h"
#include "engine/kind_interface/procedure_study.h"
#include "sampling/random_stream.h"
#include "sampling/statistics.h"

namespace poise::optimize {
namespace {
using nlohmann::json;

std::string signed_number(double v) {
  const std::string s = short_number(v);
  return v > 0 ? "+" + s : s;
}

json difference_json(const Difference& d) {
  json j{{"difference", d.value}, {"paired", d.paired}};
  if (d.lo) j["lo"] = *d.lo;
  if (d.hi) j["hi"] = *d.hi;
  if (std::isfinite(d.share_b_ahead)) j["bootstrap_share_reference_ahead"] = d.share_b_ahead;
  return j;
}

std::string parameter_value(const OptimizationSpec& spec, const std::string& parameter, const std::string& value) {
  std::vector<std::string> keys;
  for (const auto& c : spec.choices) keys.push_back(c.parameter);
  return choice_key_label(parameter, keys) + " = " + value;
}

}  // namespace

Difference difference(const std::vector<double>& a, const std::vector<std::size_t>& a_units,
                      const std::vector<double>& b, const std::vector<std::size_t>& b_units, const std::string& stat,
                      std::uint64_t seed, int resamples) {
  Difference d;
  d.value = engine::statistic(a, stat) - engine::statistic(b, stat);
  d.paired = a.size() == b.size() && a_units == b_units;
  if (a.size() < 2 || b.size() < 2) return d;
  sampling::RandomStream rs(seed, sampling::StreamId::kBootstrap, 1);
  std::vector<double> diffs(static_cast<std::size_t>(resamples)), ra(a.size()), rb(b.size());
  std::size_t ahead = 0;
  for (auto& x : diffs) {
    for (std::size_t k = 0; k < ra.size(); ++k) {
      const auto i = static_cast<std::size_t>(rs.uniform() * static_cast<double>(a.size()));
      ra[k] = a[i];
      if (d.paired) rb[k] = b[i];
    }
    if (!d.paired) {
      for (auto& v : rb) v = b[static_cast<std::size_t>(rs.uniform() * static_cast<double>(b.size()))];
    }
    x = engine::statistic(ra, stat) - engine::statistic(rb, stat);
    ahead += x > 0 ? 1 : 0;
  }
  std::sort(diffs.begin(), diffs.end());
  d.lo = sampling::quantile_sorted(diffs, 0.025).value;
  d.hi = sampling::quantile_sorted(diffs, 0.975).value;
  d.share_b_ahead = static_cast<double>(ahead) / static_cast<double>(resamples);
  return d;
}

Equivalence equivalence(const Difference& d, double margin) {
  Equivalence e;
  e.margin = margin;
  if (!d.lo || !d.hi) {
    e.exceeds = "both";
    return e;
  }
  const bool up = *d.hi > margin, down = *d.lo < -margin;
  e.shown = !up && !down;
  e.worse = *d.lo > margin;
  e.better = *d.hi < -margin;
  e.exceeds = up && down ? "both" : up ? "upper" : down ? "lower" : "";
  return e;
}

std::string equivalence_clause(const Difference& d, const Equivalence& e, const std::string& unit,
                               const std::string& margin_text, const std::string& subject) {
  const std::string u = unit.empty() ? "" : " " + unit;
  std::string s = "difference " + signed_number(d.value);
  if (d.lo && d.hi) s += " [" + signed_number(*d.lo) + ", " + signed_number(*d.hi) + "]";
  s += u + ", which ";
  const std::string m = margin_text + " margin (" + short_number(e.margin) + u + ")";
  if (e.shown) return s + "lies within the " + m + ", so equivalence is shown";
  if (e.worse)
    return s + "lies wholly above the " + m + ", so equivalence is ruled out: " + subject +
           " is worse beyond the margin";
  if (e.better)
    return s + "lies wholly below the " + m + ", so equivalence is ruled out: " + subject +
           " is better beyond the margin";
  if (!d.lo || !d.hi) return s + "has no interval, so equivalence is NOT shown";
  if (e.exceeds == "both") {
    return s + "exceeds the " + m +
           " on both sides, so equivalence is NOT shown (the interval is wider than the "
           "margin: these fresh samples cannot resolve it)";
  }
  return s + "exceeds the " + m + " on the " + e.exceeds + " side, so equivalence is NOT shown";
}

namespace {

/// One fresh set of one combination's design: `model_of` is the base study to run (the full
/// model, or the fast one for the selection set of a fast search).
FreshCheck fresh_set(const OptimizationSpec& spec, const ChoiceResult& run, bool selection, int threads,
                     RunProgress& progress) {
  const auto design = overrides_of(spec, run.result.x, run.choice);
  const bool fast = selection && spec.fast_search;
  const std::uint64_t seed = selection ? spec.selection_seed() : spec.verification_seed;
  const auto e =
      engine::evaluate_study(fast ? spec.search_study() : spec.base, design, spec.verification_samples, seed, threads);
  FreshCheck f = check_design(spec, run.result.x, e, seed);
  progress.step(static_cast<double>(spec.verification_samples),
                std::string("[") + choice_label(run.choice) + "] " + (selection ? "selection" : "comparison") +
                    " set, " + std::to_string(spec.verification_samples) + " fresh samples" +
                    (fast ? " (fast model)" : "") + ": objective " + short_number(f.objective_value) +
                    ", constraints " + to_string(f.verdict),
                fast);
  return f;
}

/// Every feasible combination's design on the selection set.
std::vector<ChoiceOnFresh> run_selection_set(const OptimizationSpec& spec, const std::vector<ChoiceResult>& runs,
                                             int threads, RunProgress& progress) {
  std::vector<ChoiceOnFresh> fresh;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    if (runs[r].result.feasible) fresh.push_back({r, {}, {}, false});
  }
  progress.plan(static_cast<double>(fresh.size() * spec.verification_samples));
  for (auto& c : fresh) c.selection = fresh_set(spec, runs[c.run], true, threads, progress);
  return fresh;
}

/// What the decision reads: the runs, each feasible combination on the fresh sets (by run),
/// and the bootstrap of paired differences on the comparison set.
struct Fresh {
  const OptimizationSpec& spec;
  const std::vector<ChoiceResult>& runs;
  std::vector<const ChoiceOnFresh*> of;  ///< by run; null: not feasible

  /// The best on the selection set among the admitted combinations.
  template <class Admit>
  std::optional<std::size_t> pick(Admit&& admit) const {
    std::optional<std::size_t> best;
    for (std::size_t r = 0; r < of.size(); ++r) {
      if (!of[r] || !admit(*of[r])) continue;
      if (!best || of[r]->selection.objective_value < of[*best]->selection.objective_value) best = r;
    }
    return best;
  }
  /// The best combination with `parameter` = `value`: among those meeting their constraints on
  /// the selection set when any does.
  std::optional<std::size_t> best_with(const std::string& parameter, const std::string& value) const {
    auto p = pick(
        [&](const ChoiceOnFresh& c) { return c.selection.stated_met && runs[c.run].choice.at(parameter) == value; });
    return p ? p : pick([&](const ChoiceOnFresh& c) { return runs[c.run].choice.at(parameter) == value; });
  }
  /// What the comparison set must see: with a fast search, the selection set's pick and each
  /// choice value's best combination (all the decision and the answer compare); otherwise
  /// every feasible combination.
  std::vector<std::size_t> finalists() const {
    std::vector<std::size_t> out;
    auto add = [&](std::optional<std::size_t> r) {
      if (r && std::find(out.begin(), out.end(), *r) == out.end()) out.push_back(*r);
    };
    if (!spec.fast_search) {
      for (std::size_t r = 0; r < of.size(); ++r) add(of[r] ? std::optional<std::size_t>(r) : std::nullopt);
      return out;
    }
    std::optional<std::size_t> h = pick([](const ChoiceOnFresh& c) { return c.selection.stated_met; });
    add(h ? h : pick([](const ChoiceOnFresh&) { return true; }));
    for (const auto& ch : spec.choices) {
      for (const auto& v : ch.values) add(best_with(ch.parameter, v));
    }
    return out;
  }
  /// stat(a) - stat(b) on the comparison set, paired.
  Difference minus(std::size_t a, std::size_t b) const {
    return difference(of[a]->comparison.objective_values, of[a]->comparison.ok_index,
                      of[b]->comparison.objective_values, of[b]->comparison.ok_index, spec.objective_statistic,
                      spec.verification_seed);
  }
  double margin_against(std::size_t reference) const {
    return spec.equivalence_relative ? spec.equivalence_margin * std::fabs(of[reference]->comparison.objective_value)
                                     : spec.equivalence_margin;
  }
  /// The second objective on the comparison set ([pareto]); NaN without one.
  double second(std::size_t r) const {
    return spec.pareto && of[r]->comparison.second ? of[r]->comparison.second->value : NAN;
  }
};

/// The first choice parameter with more than one value: the one the answer is about.
const Choice* deciding_parameter(const OptimizationSpec& spec) {
  for (const auto& ch : spec.choices) {
    if (ch.values.size() >= 2) return &ch;
  }
  return nullptr;
}

/// The headline after the intervals have spoken: the selection set's pick stays unless another
/// value of the deciding parameter is cheaper in the second objective and the pick is not
/// shown better than it on the comparison set (its paired difference interval does not lie
/// wholly below zero) or is shown equivalent to it; then the cheapest such value's combination.
std::size_t decided_headline(const Fresh& f, std::size_t pick) {
  const Choice* ch = deciding_parameter(f.spec);
  if (!ch || !f.spec.pareto || f.spec.objective_output.empty() || !std::isfinite(f.second(pick))) return pick;
  std::size_t chosen = pick;
  for (const auto& value : ch->values) {
    const auto p = f.best_with(ch->parameter, value);
    if (!p || *p == pick || !f.of[*p]->comparison.stated_met || !(f.second(*p) < f.second(chosen))) continue;
    const Difference d = f.minus(pick, *p);  // the pick minus the cheaper one
    const bool pick_shown_better = d.hi && *d.hi < 0.0;
    if (!pick_shown_better || equivalence(d, f.margin_against(*p)).shown) chosen = *p;
  }
  return chosen;
}

std::string ratio_text(double a, double b) { return significant(a / b, 2); }

/// The decision in words: `chosen` against `other` (the best combination of another value of
/// the deciding parameter), from the paired difference's interval and, where it shows
/// nothing, the second objective.
std::string decision_sentence(const Fresh& f, const Choice& ch, std::size_t chosen, std::size_t other,
                              std::size_t selection_pick, const std::string& unit) {
  const OptimizationSpec& spec = f.spec;
  const std::string a = parameter_value(spec, ch.parameter, f.runs[chosen].choice.at(ch.parameter));
  const std::string b = parameter_value(spec, ch.parameter, f.runs[other].choice.at(ch.parameter));
  const std::string what = spec.objective_statistic + " of " + spec.objective_output;
  const FreshCheck& A = f.of[chosen]->comparison;
  const FreshCheck& B = f.of[other]->comparison;
  const Difference d = f.minus(chosen, other);
  const Equivalence e = equivalence(d, f.margin_against(chosen));  // as the by-value table states it
  const std::string u = unit.empty() ? "" : " " + unit;
  const std::string figures = interval_text(*A.objective, unit) + " with " + a + " against " +
                              interval_text(*B.objective, unit) + " with " + b + ", paired difference (" + a +
                              " minus " + b + ") " + signed_number(d.value) +
                              (d.lo && d.hi ? " [" + signed_number(*d.lo) + ", " + signed_number(*d.hi) + "]" : "") + u;
  std::string s;
  if (e.shown) {
    s = a + " and " + b + " are equivalent within " + spec.equivalence_margin_text + " on fresh samples: " + what +
        " " + figures + " (the interval lies within +-" + short_number(e.margin) + u + ")";
  } else if (d.hi && *d.hi < 0.0) {
    s = a + " is better than " + b + " on fresh samples: " + what + " " + figures + " (the interval excludes zero)";
  } else if (d.lo && *d.lo > 0.0) {
    s = a + " is kept although " + b + " did better on the comparison set: " + what + " " + figures +
        "; the selection set's pick is not confirmed";
  } else {
    const double hide = d.lo && d.hi ? std::max(std::fabs(*d.lo), std::fabs(*d.hi)) : NAN;
    s = "No difference in " + what + " between " + a + " and " + b + " was shown on fresh samples: " + figures +
        (std::isfinite(hide) ? ", so a difference of up to " + short_number(hide) + u + " (" +
                                   short_number(100.0 * hide / std::fabs(B.objective_value)) + "% of " + b +
                                   "'s) can still hide in the data"
                             : ", with no interval");
  }
  if (!e.shown) {
    s += "; equivalence within " + spec.equivalence_margin_text + " is " +
         (e.worse || e.better ? "ruled out" : "NOT shown");
  }
  const double sa = f.second(chosen), sb = f.second(other);
  if (std::isfinite(sa) && std::isfinite(sb) && sa > 0.0 && sb > 0.0) {
    const std::string second = spec.pareto->statistic + " of " + spec.pareto->output;
    const std::string su = output_unit(spec, spec.pareto->output);
    const std::string cheaper = sa <= sb ? a : b;
    s += "; " + cheaper + " takes " + ratio_text(std::max(sa, sb), std::min(sa, sb)) + " times less " + second + " (" +
         short_number(std::min(sa, sb)) + " against " + short_number(std::max(sa, sb)) + (su.empty() ? "" : " " + su) +
         ")";
    if (chosen != selection_pick) s += ", which decides, since the data show " + b + " no better in " + what;
  }
  return s;
}

/// A row of the comparison table: a combination on both fresh sets, against the headline.
json choice_row(const Fresh& f, std::size_t r, std::size_t headline, std::size_t selection_pick,
                std::size_t optimization_pick) {
  json row{{"choice", f.runs[r].choice},
           {"label", choice_label(f.runs[r].choice)},
           {"feasible", f.runs[r].result.feasible},
           {"optimization_pick", r == optimization_pick},
           {"selection_pick", r == selection_pick},
           {"best", r == headline}};
  const ChoiceOnFresh* c = f.of[r];
  if (!c) return row;
  row["selection"] = {{"objective", c->selection.objective_value},
                      {"constraints_met", c->selection.stated_met},
                      {"model", f.spec.fast_search ? "fast" : "full"}};
  row["compared"] = c->compared;
  if (!c->compared) return row;  // not a finalist: the selection set (fast model) alone
  row["comparison"] = c->comparison.to_json();
  row["objective"] = c->comparison.objective ? interval_json(*c->comparison.objective)
                                             : json{{"value", c->comparison.objective_value}};
  if (c->comparison.second) row["second"] = interval_json(*c->comparison.second);
  if (r == headline) return row;
  if (!f.spec.objective_output.empty()) {
    row["minus_best"] = difference_json(f.minus(r, headline));
  } else {
    row["minus_best"] = {{"difference", c->comparison.objective_value - f.of[headline]->comparison.objective_value}};
  }
  return row;
}

/// Per value of each choice parameter: its best combination (picked on the selection set)
/// against the headline's value on the comparison set.
json by_parameter_json(const Fresh& f, std::size_t headline, const json& rows, const std::string& unit) {
  const OptimizationSpec& spec = f.spec;
  json by = json::array();
  for (const auto& ch : spec.choices) {
    if (ch.values.size() < 2) continue;
    const std::string hv = f.runs[headline].choice.at(ch.parameter);
    json values = json::array();
    for (const auto& val : ch.values) {
      json j{{"value", val}, {"headline_value", val == hv}};
      const auto p = val == hv ? std::optional<std::size_t>(headline) : f.best_with(ch.parameter, val);
      if (p) {
        const ChoiceOnFresh* c = f.of[*p];
        j["run"] = *p;
        j["choice"] = f.runs[*p].choice;
        j["label"] = choice_label(f.runs[*p].choice);
        j["objective"] = rows[*p]["objective"];
        j["constraints"] = to_string(c->comparison.verdict);
        if (c->comparison.second) j["second"] = interval_json(*c->comparison.second);
        if (val != hv && !spec.objective_output.empty()) {
          const Difference d = f.minus(*p, headline);
          const Equivalence e = equivalence(d, f.margin_against(headline));
          j["minus_best"] = difference_json(d);
          j["equivalence"] = {{"margin", e.margin},
                              {"shown", e.shown},
                              {"worse_beyond_margin", e.worse},
                              {"better_beyond_margin", e.better},
                              {"exceeds", e.exceeds},
                              {"text", equivalence_clause(d, e, unit, spec.equivalence_margin_text,
                                                          parameter_value(spec, ch.parameter, val))}};
        }
      }
      values.push_back(j);
    }
    by.push_back({{"parameter", ch.parameter}, {"headline_value", hv}, {"values", values}});
  }
  return by;
}

}  // namespace

ChoiceDecision decide_choices(const OptimizationSpec& spec, const std::vector<ChoiceResult>& runs,
                              std::size_t optimization_pick, int threads, RunProgress& progress) {
  ChoiceDecision out;
  const std::string unit = spec.objective_output.empty() ? (spec.variables.empty() ? "" : spec.variables[0].unit)
                                                         : output_unit(spec, spec.objective_output);
  out.fresh = run_selection_set(spec, runs, threads, progress);
  Fresh f{spec, runs, std::vector<const ChoiceOnFresh*>(runs.size(), nullptr)};
  for (const auto& c : out.fresh) f.of[c.run] = &c;
  const std::vector<std::size_t> finalists = f.finalists();
  progress.plan(static_cast<double>(finalists.size() * spec.verification_samples));
  for (auto& c : out.fresh) {
    if (std::find(finalists.begin(), finalists.end(), c.run) == finalists.end()) continue;
    c.comparison = fresh_set(spec, runs[c.run], false, threads, progress);
    c.compared = true;
  }
  // The selection set's pick: the best there among the combinations meeting their constraints
  // there (as stated); if none does, the best there overall. Then the intervals decide.
  std::optional<std::size_t> h = f.pick([](const ChoiceOnFresh& c) { return c.selection.stated_met; });
  out.headline_met_on_selection = h.has_value();
  if (!h) h = f.pick([](const ChoiceOnFresh&) { return true; });
  const std::size_t selection_pick = h ? *h : optimization_pick;
  out.headline = h ? decided_headline(f, selection_pick) : optimization_pick;
  json rows = json::array();
  for (std::size_t r = 0; r < runs.size(); ++r)
    rows.push_back(choice_row(f, r, out.headline, selection_pick, optimization_pick));
  out.json = {{"output", spec.objective_output},
              {"statistic", spec.objective_statistic},
              {"samples", spec.verification_samples},
              {"selection_seed", spec.selection_seed()},
              {"comparison_seed", spec.verification_seed},
              {"headline", out.headline},
              {"selection_pick", selection_pick},
              {"headline_met_constraints_on_selection_set", out.headline_met_on_selection},
              {"equivalence_margin", spec.equivalence_margin_text},
              {"choices", rows}};
  if (!h) return out;
  out.json["by_parameter"] = by_parameter_json(f, out.headline, rows, unit);
  if (spec.objective_output.empty()) {
    std::size_t met_count = 0;
    for (const auto& c : out.fresh) met_count += c.comparison.stated_met ? 1 : 0;
    out.sentence = choice_label(runs[out.headline].choice) + " gives the smallest objective (" +
                   short_number(f.of[out.headline]->comparison.objective_value) + (unit.empty() ? "" : " " + unit) +
                   ") of the combinations meeting their constraints on fresh samples (" + std::to_string(met_count) +
                   " of " + std::to_string(runs.size()) + " did on the comparison set)";
    return out;
  }
  // The answer compares the headline with the strongest other value of the deciding parameter
  // (the best of the others on the selection set).
  if (const Choice* ch = deciding_parameter(spec)) {
    std::optional<std::size_t> other;
    for (const auto& val : ch->values) {
      if (val == runs[out.headline].choice.at(ch->parameter)) continue;
      const auto p = f.best_with(ch->parameter, val);
      if (p && f.of[*p]->comparison.objective && f.of[out.headline]->comparison.objective &&
          (!other || f.of[*p]->selection.objective_value < f.of[*other]->selection.objective_value)) {
        other = p;
      }
    }
    if (other) out.sentence = decision_sentence(f, *ch, out.headline, *other, selection_pick, unit);
  }
  return out;
}

}  // namespace poise::optimize
