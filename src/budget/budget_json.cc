#include "budget/budget_json.h"

#include <cmath>

#include "core/units.h"

namespace poise::budget {
namespace {

using nlohmann::json;

json optional_number(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

json declared_json(const Declared& d, double factor) {
  if (!d.present) return nullptr;
  if (d.ranged) return json::array({d.least / factor, d.greatest / factor});
  return d.greatest / factor;
}

void put_verdict(json& j, const Verdict& v) {
  j["relative_difference"] = optional_number(v.relative_difference);
  if (v.relative_difference_least || v.relative_difference_greatest) {
    j["relative_difference_least"] = optional_number(v.relative_difference_least);
    j["relative_difference_greatest"] = optional_number(v.relative_difference_greatest);
    j["verdict_least"] = v.verdict_least;
    j["verdict_greatest"] = v.verdict_greatest;
  }
  if (!v.compared.empty()) j["compared"] = v.compared;
  j["verdict"] = v.verdict;
  if (!v.slip.empty()) j["slip"] = v.slip;
}

void put_range(json& j, const Range& r, double factor) {
  if (r.varies()) {
    j["recomputed_min"] = r.least / factor;
    j["recomputed_max"] = r.greatest / factor;
  } else {
    j["recomputed"] = r.greatest / factor;
  }
}

json item_json(const ItemResult& r, const BudgetSpec& spec, bool given, double given_value) {
  const double f = spec.unit_factor;
  json j{{"name", r.name}, {"kind", r.bias ? "bias" : "random"}, {"line", r.line}};
  if (given) {
    j["value"] = given_value / f;
  } else {
    put_range(j, r.recomputed, f);
  }
  j["declared"] = declared_json(r.declared, f);
  if (r.declared.present) j["declared_as_written"] = r.declared.as_written;
  put_verdict(j, r.verdict);
  if (r.group) {
    j["members"] = r.members;
    j["combination"] = to_string(r.combination);
    if (r.from_members_declared) {
      j["from_members_declared"] = {{"least", r.from_members_declared->least / f},
                                    {"greatest", r.from_members_declared->greatest / f}};
    }
  }
  if (!r.model_key.empty()) j["model_key"] = r.model_key;
  j["unit"] = spec.unit;
  return j;
}

json field_point(const BudgetSpec& spec, const std::vector<double>& x) {
  json p = json::object();
  for (std::size_t k = 0; k < spec.field.size() && k < x.size(); ++k) {
    const auto& v = spec.field[k];
    p[v.name] = v.unit.empty() ? x[k] : x[k] / units::unit_factor(v.unit);
  }
  return p;
}

// The combined figure: its bounds, where in the field they fall, the declared figure and its
// verdict, and the same in pixels where the budget has a pixel.
json combined_json(const BudgetSpec& spec, const BudgetResult& res) {
  const double f = spec.unit_factor;
  json combined{{"least", res.combined.least / f},
                {"greatest", res.combined.greatest / f},
                {"unit", spec.unit},
                {"level", std::to_string(spec.level) + "sigma"},
                {"combination", to_string(spec.combination)},
                {"least_at", field_point(spec, res.least_at)},
                {"greatest_at", field_point(spec, res.greatest_at)},
                {"declared", declared_json(spec.declared, f)}};
  put_verdict(combined, res.combined_verdict);
  if (res.combined_from_declared) {
    combined["from_declared"] = {{"least", res.combined_from_declared->least / f},
                                 {"greatest", res.combined_from_declared->greatest / f}};
  }
  if (spec.pixel) {
    combined["pixel"] = *spec.pixel / f;
    combined["least_px"] = res.combined.least / *spec.pixel;
    combined["greatest_px"] = res.combined.greatest / *spec.pixel;
    if (spec.declared_in_pixels.present) {
      json px{{"declared", declared_json(spec.declared_in_pixels, 1.0)}};
      put_verdict(px, res.pixels_verdict);
      combined["in_pixels"] = std::move(px);
    }
  }
  return combined;
}

}  // namespace

json budget_json(const BudgetSpec& spec, const BudgetResult& res) {
  const double f = spec.unit_factor;
  json field = json::array();
  for (const auto& v : spec.field) {
    const double uf = v.unit.empty() ? 1.0 : units::unit_factor(v.unit);
    field.push_back({{"name", v.name}, {"least", v.lo / uf}, {"greatest", v.hi / uf}, {"unit", v.unit}});
  }
  json out;
  out["budget"] = {{"name", spec.name},
                   {"title", spec.title},
                   {"notes", spec.notes},
                   {"source", spec.source},
                   {"file", spec.file},
                   {"unit", spec.unit},
                   {"level", std::to_string(spec.level) + "sigma"},
                   {"combination", to_string(spec.combination)},
                   {"confidence", spec.confidence},
                   {"requirement", spec.requirement ? json(*spec.requirement / f) : json(nullptr)},
                   {"requirement_as_written", spec.requirement_text},
                   {"field", field},
                   {"field_grid_points", res.grid_points}};
  json lines = json::array();
  for (std::size_t i = 0; i < res.lines.size(); ++i) {
    const LineSpec& l = spec.lines[i];
    json j = item_json(res.lines[i], spec, l.given, l.value);
    if (!l.given) {
      j["tolerance"] = l.tolerance_text;
      if (l.lever) j["lever"] = l.lever_text;
      j["distribution"] = sampling::to_string(l.distribution);
      j["tolerance_is"] = sampling::to_string(l.convention);
      j["gain"] = l.gain;
    }
    if (!l.propagation.empty()) j["propagation"] = l.propagation;
    lines.push_back(std::move(j));
  }
  out["lines"] = std::move(lines);
  json groups = json::array();
  for (std::size_t g = 0; g < res.groups.size(); ++g) {
    json j = item_json(res.groups[g], spec, false, 0.0);
    if (!spec.groups[g].propagation.empty()) j["propagation"] = spec.groups[g].propagation;
    groups.push_back(std::move(j));
  }
  out["groups"] = std::move(groups);
  out["combined"] = combined_json(spec, res);
  out["at_confidence"] = {{"least", res.at_confidence.least / f},
                          {"greatest", res.at_confidence.greatest / f},
                          {"unit", spec.unit},
                          {"confidence", spec.confidence},
                          {"multiple", res.multiple},
                          {"random_scale", res.random_scale}};
  out["requirement_met"] = res.requirement_met ? json(*res.requirement_met) : json(nullptr);
  if (res.requirement_met) {
    out["requirement_met_note"] =
        "requirement_met is the combination rule's verdict alone; where the budget has a "
        "model, the Monte Carlo of its exact chain decides (requirement_verdict, answer)";
  }
  return out;
}

}  // namespace poise::budget
