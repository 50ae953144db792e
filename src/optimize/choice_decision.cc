#include "optimize/choice_decision.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sampling/random_stream.h"
#include "sampling/statistics.h"
#include "engine/kind_interface/procedure_study.h"

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
  if (e.worse) return s + "lies wholly above the " + m + ", so equivalence is ruled out: " + subject + " is worse beyond the margin";
  if (e.better) return s + "lies wholly below the " + m + ", so equivalence is ruled out: " + subject + " is better beyond the margin";
  if (!d.lo || !d.hi) return s + "has no interval, so equivalence is NOT shown";
  if (e.exceeds == "both") {
    return s + "exceeds the " + m + " on both sides, so equivalence is NOT shown (the interval is wider than the "
               "margin: these fresh samples cannot resolve it)";
  }
  return s + "exceeds the " + m + " on the " + e.exceeds + " side, so equivalence is NOT shown";
}

ChoiceDecision decide_choices(const OptimizationSpec& spec, const std::vector<ChoiceResult>& runs,
                              std::size_t optimization_pick, int threads, RunProgress& progress) {
  ChoiceDecision out;
  const std::string stat = spec.objective_statistic;
  const std::string unit = spec.objective_output.empty() ? (spec.variables.empty() ? "" : spec.variables[0].unit)
                                                         : output_unit(spec, spec.objective_output);
  std::vector<std::size_t> feasible;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    if (runs[r].result.feasible) feasible.push_back(r);
  }
  progress.plan(2.0 * static_cast<double>(feasible.size() * spec.verification_samples));
  std::vector<const ChoiceOnFresh*> of(runs.size(), nullptr);
  for (std::size_t r : feasible) {
    ChoiceOnFresh c;
    c.run = r;
    const auto design = overrides_of(spec, runs[r].result.x, runs[r].choice);
    for (int set = 0; set < 2; ++set) {
      const std::uint64_t seed = set == 0 ? spec.selection_seed() : spec.verification_seed;
      const auto e = engine::evaluate_study(spec.base, design, spec.verification_samples, seed, threads);
      FreshCheck f = check_design(spec, runs[r].result.x, e, seed);
      progress.step(static_cast<double>(spec.verification_samples),
                    "[" + choice_label(runs[r].choice) + "] " + (set == 0 ? "selection" : "comparison") + " set, " +
                        std::to_string(spec.verification_samples) + " fresh samples: objective " +
                        short_number(f.objective_value) + ", constraints " + to_string(f.verdict));
      (set == 0 ? c.selection : c.comparison) = std::move(f);
    }
    out.fresh.push_back(std::move(c));
  }
  for (const auto& c : out.fresh) of[c.run] = &c;
  // The headline: best on the selection set among the combinations meeting their
  // constraints there (as stated); if none does, best on the selection set overall.
  auto pick = [&](auto&& admit) {
    std::optional<std::size_t> best;
    for (const auto& c : out.fresh) {
      if (!admit(c)) continue;
      if (!best || c.selection.objective_value < of[*best]->selection.objective_value) best = c.run;
    }
    return best;
  };
  auto met = [](const ChoiceOnFresh& c) { return c.selection.stated_met; };
  auto any = [](const ChoiceOnFresh&) { return true; };
  std::optional<std::size_t> h = pick(met);
  out.headline_met_on_selection = h.has_value();
  if (!h) h = pick(any);
  out.headline = h ? *h : optimization_pick;
  const ChoiceOnFresh* H = of[out.headline];
  auto diff_to_headline = [&](std::size_t r) {
    const ChoiceOnFresh* c = of[r];
    return difference(c->comparison.objective_values, c->comparison.ok_index, H->comparison.objective_values,
                      H->comparison.ok_index, stat, spec.verification_seed);
  };
  const bool statistic_objective = !spec.objective_output.empty();
  auto margin_of = [&]() {
    return spec.equivalence_relative ? spec.equivalence_margin * std::fabs(H->comparison.objective_value)
                                     : spec.equivalence_margin;
  };
  json rows = json::array();
  for (std::size_t r = 0; r < runs.size(); ++r) {
    json row{{"choice", runs[r].choice}, {"label", choice_label(runs[r].choice)}, {"feasible", runs[r].result.feasible},
             {"optimization_pick", r == optimization_pick}, {"best", H && r == out.headline}};
    if (const ChoiceOnFresh* c = of[r]) {
      row["selection"] = {{"objective", c->selection.objective_value}, {"constraints_met", c->selection.stated_met}};
      row["comparison"] = c->comparison.to_json();
      row["objective"] = c->comparison.objective ? interval_json(*c->comparison.objective)
                                                 : json{{"value", c->comparison.objective_value}};
      if (c->comparison.second) row["second"] = interval_json(*c->comparison.second);
      if (statistic_objective && r != out.headline) row["minus_best"] = difference_json(diff_to_headline(r));
      if (!statistic_objective && r != out.headline) {
        row["minus_best"] = {{"difference", c->comparison.objective_value - H->comparison.objective_value}};
      }
    }
    rows.push_back(row);
  }
  out.json = {{"output", spec.objective_output}, {"statistic", stat}, {"samples", spec.verification_samples},
              {"selection_seed", spec.selection_seed()}, {"comparison_seed", spec.verification_seed},
              {"headline", out.headline}, {"headline_met_constraints_on_selection_set", out.headline_met_on_selection},
              {"equivalence_margin", spec.equivalence_margin_text}, {"choices", rows}};
  if (!H) return out;
  // Per value of each choice parameter: its best combination picked on the selection set,
  // compared with the headline on the comparison set.
  json by = json::array();
  std::vector<std::string> sentences;
  for (const auto& ch : spec.choices) {
    if (ch.values.size() < 2) continue;
    const std::string hv = runs[out.headline].choice.at(ch.parameter);
    json values = json::array();
    for (const auto& val : ch.values) {
      auto p = pick([&](const ChoiceOnFresh& c) { return c.selection.stated_met && runs[c.run].choice.at(ch.parameter) == val; });
      if (!p) p = pick([&](const ChoiceOnFresh& c) { return runs[c.run].choice.at(ch.parameter) == val; });
      json j{{"value", val}, {"headline_value", val == hv}};
      if (!p) {
        values.push_back(j);
        continue;
      }
      const ChoiceOnFresh* c = of[*p];
      j["run"] = *p;
      j["choice"] = runs[*p].choice;
      j["label"] = choice_label(runs[*p].choice);
      j["objective"] = rows[*p]["objective"];
      j["constraints"] = to_string(c->comparison.verdict);
      if (c->comparison.second) j["second"] = interval_json(*c->comparison.second);
      if (val != hv && statistic_objective) {
        const Difference d = diff_to_headline(*p);
        const Equivalence e = equivalence(d, margin_of());
        j["minus_best"] = difference_json(d);
        j["equivalence"] = {{"margin", e.margin}, {"shown", e.shown}, {"worse_beyond_margin", e.worse},
                            {"better_beyond_margin", e.better}, {"exceeds", e.exceeds},
                            {"text", equivalence_clause(d, e, unit, spec.equivalence_margin_text,
                                                        parameter_value(spec, ch.parameter, val))}};
        // The decision in words, for the first parameter with more than one value.
        if (sentences.empty()) {
          const std::string a = parameter_value(spec, ch.parameter, val), b = parameter_value(spec, ch.parameter, hv);
          const std::string what = stat + " of " + spec.objective_output;
          const bool cheaper = c->comparison.second && H->comparison.second &&
                               c->comparison.second->value < H->comparison.second->value;
          std::string s;
          if (cheaper && e.shown) {
            s = a + " suffices: " + what + " " + interval_text(*c->comparison.objective, unit) + " against " +
                interval_text(*H->comparison.objective, unit) + " with " + b + " (best on fresh samples), " +
                equivalence_clause(d, e, unit, spec.equivalence_margin_text);
          } else {
            s = b + " is best on fresh samples: " + what + " " + interval_text(*H->comparison.objective, unit) +
                " against " + interval_text(*c->comparison.objective, unit) + " with " + a + "; equivalence of " + a +
                " to " + b + " within " + spec.equivalence_margin_text + " of " + what + ": " +
                equivalence_clause(d, e, unit, spec.equivalence_margin_text, a);
          }
          if (c->comparison.second && H->comparison.second && spec.pareto) {
            const double sa = c->comparison.second->value, sb = H->comparison.second->value;
            const std::string su = output_unit(spec, spec.pareto->output);
            const bool b_costlier = sb > sa;
            char ratio[32];
            std::snprintf(ratio, sizeof ratio, "%.2g", b_costlier ? sb / sa : sa / sb);
            s += "; " + (b_costlier ? b : a) + " takes " + ratio + " times the " + spec.pareto->statistic + " " +
                 spec.pareto->output + " (" + short_number(b_costlier ? sb : sa) + " against " +
                 short_number(b_costlier ? sa : sb) + (su.empty() ? "" : " " + su) + ")";
          }
          sentences.push_back(s);
        }
      }
      values.push_back(j);
    }
    by.push_back({{"parameter", ch.parameter}, {"headline_value", hv}, {"values", values}});
  }
  out.json["by_parameter"] = by;
  if (!sentences.empty()) out.sentence = sentences.front();
  if (!statistic_objective) {
    std::size_t met_count = 0;
    for (const auto& c : out.fresh) met_count += c.comparison.stated_met ? 1 : 0;
    out.sentence = choice_label(runs[out.headline].choice) + " gives the smallest objective (" +
                   short_number(H->comparison.objective_value) + (unit.empty() ? "" : " " + unit) +
                   ") of the combinations meeting their constraints on fresh samples (" + std::to_string(met_count) +
                   " of " + std::to_string(runs.size()) + " did on the comparison set)";
  }
  return out;
}

}  // namespace poise::optimize
