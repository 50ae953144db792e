#include "budget/budget_check.h"

#include <cmath>
#include <functional>

#include "budget/slip_detection.h"

namespace poise::budget {
namespace {

constexpr double kAgreement = 0.01;  // "agrees": within 1% of the recomputed value

std::optional<double> relative(double declared, double recomputed) {
  if (recomputed == 0.0) return std::nullopt;
  return (declared - recomputed) / recomputed;
}

bool end_agrees(double declared, double recomputed) {
  if (recomputed == 0.0) return declared == 0.0;
  return std::abs(declared - recomputed) <= kAgreement * std::abs(recomputed) * (1.0 + 1e-9);
}

// The items' results as they are checked: every line's and group's, and which are finished
// (a group's slip detection reads its members' results).
struct ItemChecks {
  const BudgetSpec& spec;
  const BudgetEvaluator& ev;
  std::vector<ItemResult> items;
  std::vector<const ItemResult*> done;

  ItemChecks(const BudgetSpec& s, const BudgetEvaluator& e)
      : spec(s), ev(e), items(e.items()), done(e.items(), nullptr) {}

  // Line i: recomputed from its inputs, against its declared value.
  void check_line(std::size_t i) {
    const Mode plain;
    const LineSpec& l = spec.lines[i];
    ItemResult& r = items[i];
    r.name = l.name;
    r.line = l.line;
    r.bias = l.kind == LineKind::kBias;
    r.model_key = l.model_key;
    r.declared = l.declared;
    r.recomputed = ev.item_range(i, plain);
    if (l.given) {
      r.verdict.verdict = "given";
    } else {
      r.tolerance_sigma = tolerance_sigma(l);
      r.verdict = compare(l.declared, r.recomputed);
      if (r.verdict.verdict == "disagrees") r.verdict.slip = line_slip(ev, i, l.declared, r.recomputed);
    }
    done[i] = &r;
  }

  // A group, after its members (members may be groups): recomputed from them, and from their
  // declared values where any declares one.
  void check_group(std::size_t item) {
    if (done[item]) return;
    for (std::size_t m : ev.members(item)) {
      if (ev.is_group(m)) check_group(m);
    }
    const Mode plain;
    const GroupSpec& g = spec.groups[item - spec.lines.size()];
    ItemResult& r = items[item];
    r.name = g.name;
    r.group = true;
    r.line = g.line;
    r.bias = ev.is_bias(item);
    r.members = g.members;
    r.combination = g.combination;
    r.declared = g.declared;
    r.recomputed = ev.item_range(item, plain);
    bool any_declared = false;
    for (std::size_t m : ev.members(item)) any_declared = any_declared || ev.declared(m).present;
    if (any_declared) {
      Mode lo, hi;
      lo.declared = Mode::Declared::kLeast;
      hi.declared = Mode::Declared::kGreatest;
      r.from_members_declared = Range{ev.item_range(item, lo).least, ev.item_range(item, hi).greatest};
    }
    r.verdict = compare(g.declared, r.recomputed);
    if (r.verdict.verdict == "disagrees") r.verdict.slip = node_slip(ev, item, g.declared, r.recomputed, done);
    done[item] = &r;
  }
};

// The combination of the top items: plainly, at the confidence, from the declared values;
// its verdicts (also in pixels) and the requirement.
void check_combined(const BudgetSpec& spec, const BudgetEvaluator& ev, const std::vector<const ItemResult*>& done,
                    BudgetResult& res) {
  const Mode plain;
  res.combined = ev.combined_range(plain, &res.least_at, &res.greatest_at);
  res.multiple = confidence_multiple(spec.confidence);
  res.random_scale = res.multiple / spec.level;
  Mode at_confidence;
  at_confidence.random_scale = res.random_scale;
  res.at_confidence = ev.combined_range(at_confidence);
  bool any_declared = false;
  for (std::size_t k : ev.top()) any_declared = any_declared || ev.declared(k).present;
  if (any_declared) {
    Mode lo, hi;
    lo.declared = Mode::Declared::kLeast;
    hi.declared = Mode::Declared::kGreatest;
    res.combined_from_declared = Range{ev.combined_range(lo).least, ev.combined_range(hi).greatest};
  }
  res.combined_verdict = compare(spec.declared, res.combined);
  if (res.combined_verdict.verdict == "disagrees") {
    res.combined_verdict.slip = node_slip(ev, std::nullopt, spec.declared, res.combined, done);
  }
  if (spec.declared_in_pixels.present && spec.pixel) {
    Declared in_si = spec.declared_in_pixels;
    in_si.least *= *spec.pixel;
    in_si.greatest *= *spec.pixel;
    res.pixels_verdict = compare(in_si, res.combined);
    if (res.pixels_verdict.verdict == "disagrees") {
      res.pixels_verdict.slip = node_slip(ev, std::nullopt, in_si, res.combined, done);
    }
  }
  if (spec.requirement) res.requirement_met = res.at_confidence.greatest <= *spec.requirement;
}

}  // namespace

bool agrees(const Declared& d, const Range& r) {
  if (!d.present) return false;
  if (d.ranged) return end_agrees(d.least, r.least) && end_agrees(d.greatest, r.greatest);
  return end_agrees(d.greatest, r.greatest);
}

Verdict compare(const Declared& d, const Range& r) {
  Verdict v;
  if (!d.present) return v;
  v.verdict = agrees(d, r) ? "agrees" : "disagrees";
  if (d.ranged) {
    v.compared = "least and greatest";
    v.relative_difference_least = relative(d.least, r.least);
    v.relative_difference_greatest = relative(d.greatest, r.greatest);
    v.verdict_least = end_agrees(d.least, r.least) ? "agrees" : "disagrees";
    v.verdict_greatest = end_agrees(d.greatest, r.greatest) ? "agrees" : "disagrees";
    const auto& a = v.relative_difference_least;
    const auto& b = v.relative_difference_greatest;
    if (a && b) {
      v.relative_difference = std::abs(*a) > std::abs(*b) ? a : b;
    } else {
      v.relative_difference = a ? a : b;
    }
  } else {
    v.compared = r.varies() ? "greatest" : "value";
    v.relative_difference = relative(d.greatest, r.greatest);
  }
  return v;
}

BudgetResult check_budget(const BudgetSpec& spec) {
  const BudgetEvaluator ev(spec);
  BudgetResult res;
  res.grid_points = ev.grid().size();
  ItemChecks checks(spec, ev);
  for (std::size_t i = 0; i < spec.lines.size(); ++i) checks.check_line(i);
  // Groups after their members (members may be groups).
  for (std::size_t k = spec.lines.size(); k < ev.items(); ++k) checks.check_group(k);
  check_combined(spec, ev, checks.done, res);
  for (std::size_t i = 0; i < spec.lines.size(); ++i) res.lines.push_back(checks.items[i]);
  for (std::size_t k = spec.lines.size(); k < ev.items(); ++k) res.groups.push_back(checks.items[k]);
  return res;
}

}  // namespace poise::budget
