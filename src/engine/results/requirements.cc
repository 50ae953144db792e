#include "engine/results/requirements.h"

#include "core/nearest_name.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>

#include "core/units.h"
#include "engine/kind_interface/study_kind.h"
#include "engine/results/confidence_bound.h"
#include "engine/results/result_io.h"
#include "engine/results/specification_limits.h"
#include "engine/study_files/toml_reader.h"

namespace poise::engine {
namespace {
using nlohmann::json;

const OutputSpec* find_output(const std::vector<OutputSpec>& outputs, const std::string& name) {
  const auto it = std::find_if(outputs.begin(), outputs.end(), [&](const OutputSpec& o) { return o.name == name; });
  return it == outputs.end() ? nullptr : &*it;
}

struct Judged {
  std::string verdict;          // met | not met | undecided | no samples
  std::optional<double> bound;  // on the requirement's side
  std::optional<double> other;  // on the other side
  std::string note;
  std::string design_note;  ///< the bounds' assumption the design does not meet
  std::optional<std::size_t> samples_to_decide;
};

// A sample extreme has no distribution-free bound on its far side: "max <= limit" is decided
// by the samples alone (a sample beyond the limit: not met; none: met by every sample run), and
// "min >= limit" mirrors it.
Judged judge_extreme(const Requirement& r, double limit, double value) {
  Judged j;
  const bool upper_extreme = r.statistic == "max";
  const std::string what = upper_extreme ? "a maximum" : "a minimum";
  if (r.at_most == upper_extreme) {  // max <= limit, min >= limit
    const bool beyond = r.at_most ? value > limit : value < limit;
    j.verdict = beyond ? "not met" : "met";
    if (!beyond) {
      j.note = "met by every sample run; " + what + " has no distribution-free " + (upper_extreme ? "upper" : "lower") +
               " bound";
    }
  } else {  // max >= limit, min <= limit
    const bool reached = r.at_most ? value <= limit : value >= limit;
    j.verdict = reached ? "met" : "not met";
    if (!reached) j.note = "no sample reached the limit; " + what + " has no distribution-free bound";
  }
  return j;
}

// The verdict of one requirement on the values, the limit in the output's unit (a
// specification's figure: `spec`).
Judged judge(const Requirement& r, const OutputValues& ov, double limit, double value,
             const std::optional<SpecificationFigure>& spec) {
  if (r.statistic == "max" || r.statistic == "min") return judge_extreme(r, limit, value);
  Judged j;
  const auto beyond = [&](double x) { return r.at_most ? x > limit : x < limit; };
  if (!ov.independent && ov.replicate_size == 0) {
    j.design_note =
        "the bounds assume independent samples; this lhs or sobol design without [sampling] "
        "replicate_size does not guarantee them (set replicate_size, or method = \"monte_carlo\")";
  }
  if (spec) {
    j.bound = spec->bound;
    j.other = spec->other;
  } else {
    const SampleSet set = sample_set(*ov.values, *ov.ok_index, ov.replicate_size);
    const BoundSpec up{BoundSide::kUpper, r.confidence}, down{BoundSide::kLower, r.confidence};
    j.bound = one_sided_bound(set, r.statistic, r.at_most ? up : down);
    j.other = one_sided_bound(set, r.statistic, r.at_most ? down : up);
  }
  if (j.bound && !beyond(*j.bound)) {
    j.verdict = "met";
  } else if (j.other && beyond(*j.other)) {
    j.verdict = "not met";
  } else {
    j.verdict = "undecided";
    // The half-width on the side facing the limit shrinks as 1/sqrt(n); the samples at which
    // it would end at the limit, were the statistic to stay where it is.
    const std::optional<double> facing = beyond(value) ? j.other : j.bound;
    const double gap = std::abs(value - limit);
    const double n = static_cast<double>(ov.values->size());
    if (!facing) {
      j.note = "too few samples for an " + std::string(r.at_most ? "upper" : "lower") + " bound of " +
               statistic_label(r.statistic);
      // A distribution-free bound of the q-quantile exists from n >= ln(1 - c) / ln(q) (upper)
      // or ln(1 - c) / ln(1 - q) (lower) samples on.
      if (r.statistic.size() > 1 && r.statistic[0] == 'p' && !is_specification_statistic(r.statistic) &&
          ov.replicate_size == 0) {
        std::string q_text = r.statistic.substr(1);
        std::replace(q_text.begin(), q_text.end(), '_', '.');
        const double q = std::stod(q_text) / 100.0;
        const double n_min = std::log(1.0 - r.confidence) / std::log(r.at_most == beyond(value) ? 1.0 - q : q);
        if (std::isfinite(n_min) && n_min > n) {
          j.samples_to_decide = static_cast<std::size_t>(std::ceil(n_min));
          j.note += " (one exists from " + std::to_string(*j.samples_to_decide) + " samples on)";
        }
      }
    } else if (gap > 0.0) {
      const double half = std::abs(*facing - value);
      j.samples_to_decide = static_cast<std::size_t>(std::ceil(n * (half / gap) * (half / gap) * 1.1));
    } else {
      j.note = "the statistic sits on the limit: no sample count decides it";
    }
  }
  return j;
}

// A specification's limits must convert to the output's unit.
void check_specification_units(const Requirement& r, const OutputSpec& o, const SourceLocation& at,
                               std::vector<InputError>& errors) {
  const units::Quantity u = unit_quantity(o.unit);
  for (const std::string& limit : r.within) {
    try {
      if (units::parse_quantity(limit).dim == u.dim) continue;
    } catch (const Error&) {
      continue;  // reported when the file was read
    }
    errors.emplace_back(at, "requirement.within", quote_value(limit),
                        "a value in a unit of " + units::dimension_name(u.dim) + " (the output " + r.output +
                            " is in " + (o.unit.empty() || o.unit == "1" ? std::string("no unit") : o.unit) + ")");
  }
}

void read_confidence_and_notes(TomlReader& t, Requirement& r) {
  r.confidence = t.number(
      "confidence",
      [](double c) {
        return c >= 0.5 && c < 1.0 ? std::string() : std::string("a one-sided confidence, 0.5 <= c < 1, e.g. 0.95");
      },
      0.95);
  t.string("notes", "");
}

}  // namespace

const std::vector<std::string>& requirement_statistics() {
  static const std::vector<std::string> kStatistics = [] {
    std::vector<std::string> names = {"mean", "min"};
    for (const sampling::SummaryQuantile& q : sampling::summary_quantiles()) names.emplace_back(q.name);
    names.emplace_back("max");
    return names;
  }();
  return kStatistics;
}

std::vector<Requirement> read_requirements(TomlReader& root) {
  std::vector<Requirement> out;
  // [requirement] as one table is a kind's shorthand (read by the kind); an array is ours.
  if (root.has("requirement") && root.raw()["requirement"].is_table()) return out;
  for (auto& t : root.table_array("requirement")) {
    Requirement r;
    r.file = t.context().file;
    r.line = t.line_of("output");
    r.origin = r.file + ":" + std::to_string(r.line);
    r.output = t.string("output");
    if (t.has("within") || t.schema_only()) {
      read_specification(t, r);
      if (!t.schema_only()) {
        read_confidence_and_notes(t, r);
        out.push_back(r);
        continue;
      }
    }
    r.statistic = t.choice("statistic", requirement_statistics(), "p95");
    const bool most = t.has("at_most"), least = t.has("at_least");
    if (most == least && !t.schema_only()) {
      t.error(most ? "at_least" : "at_most", most ? quote_value(t.string("at_least")) : "",
              "exactly one of at_most or at_least, a value with the output's unit, e.g. at_most = \"1.5 mN*m\"");
    }
    r.at_most = most || !least;
    if (t.schema_only()) {  // both, as alternatives
      t.ask("at_most", "a value with the output's unit, e.g. \"1.5 mN*m\" (or at_least)", "", false);
      t.ask("at_least", "a value with the output's unit (or at_most)", "", false);
    }
    r.limit_text =
        t.string(r.at_most ? "at_most" : "at_least", t.schema_only() ? std::optional<std::string>("") : std::nullopt);
    if (!r.limit_text.empty()) {
      try {
        units::parse_quantity(r.limit_text);
      } catch (const Error& e) {
        t.error(r.at_most ? "at_most" : "at_least", quote_value(r.limit_text),
                std::string("a number with the output's unit, e.g. \"1.5 mN*m\" (") + e.what() + ")");
      }
    }
    read_confidence_and_notes(t, r);
    out.push_back(r);
  }
  return out;
}

void check_requirements(const std::vector<Requirement>& requirements, const std::vector<OutputSpec>& outputs) {
  std::vector<InputError> errors;
  for (const auto& r : requirements) {
    const OutputSpec* o = find_output(outputs, r.output);
    const SourceLocation at{r.file, r.line, 0};
    if (!o) {
      std::string names;
      for (const auto& x : outputs) names += (names.empty() ? "" : ", ") + x.name;
      errors.emplace_back(at, "requirement.output", quote_value(r.output),
                          "an output of this study: " + names + did_you_mean(r.output, output_names_of(outputs)));
      continue;
    }
    if (is_specification_statistic(r.statistic)) {
      check_specification_units(r, *o, at, errors);
      continue;
    }
    try {
      const units::Quantity u = unit_quantity(o->unit), v = units::parse_quantity(r.limit_text);
      if (!(u.dim == v.dim)) {
        errors.emplace_back(at, r.at_most ? "requirement.at_most" : "requirement.at_least", quote_value(r.limit_text),
                            "a value in a unit of " + units::dimension_name(u.dim) + " (the output " + r.output +
                                " is in " + (o->unit.empty() || o->unit == "1" ? std::string("no unit") : o->unit) +
                                ")");
      }
    } catch (const Error&) {
      // An unparsable limit was reported when the file was read.
    }
  }
  if (!errors.empty()) throw ValidationError(errors);
}

nlohmann::json judge_requirements(const std::vector<Requirement>& requirements, const std::vector<OutputSpec>& outputs,
                                  const std::function<OutputValues(const std::string&)>& values_of) {
  json out = json::array();
  for (const auto& r : requirements) {
    const OutputSpec* o = find_output(outputs, r.output);
    if (!o) continue;  // check_requirements refused it before the run
    const bool specification = is_specification_statistic(r.statistic);
    const double limit = specification ? std::stod(r.limit_text)
                                       : units::parse_quantity(r.limit_text).value / unit_quantity(o->unit).value;
    const std::string limit_unit = specification ? (r.statistic == "ppm" ? "ppm" : "") : o->unit;
    json v{
        {"output", r.output},         {"statistic", r.statistic},
        {"at_most", r.at_most},       {"limit", {{"value", limit}, {"unit", limit_unit}, {"as_written", r.limit_text}}},
        {"confidence", r.confidence}, {"declared_in", r.origin}};
    std::optional<SpecificationFigure> spec;
    double lower = 0.0, upper = 0.0;
    if (specification) {
      std::tie(lower, upper) = specification_limits(r, o->unit);
      v["within"] = {{"lower", lower}, {"upper", upper}, {"unit", o->unit}, {"as_written", r.within}};
    }
    const OutputValues ov = values_of(r.output);
    // Every sample failed: a yield is 0 (failed samples count as outside), other figures have none.
    const bool yield_of_failures = specification && r.statistic != "cpk" && ov.values && ov.failed > 0;
    if (!ov.values || (ov.values->empty() && !yield_of_failures)) {
      v["value"] = nullptr;
      v["bound"] = nullptr;
      v["verdict"] = "undecided";
      v["note"] = "no sample of this output ran";
      out.push_back(v);
      continue;
    }
    if (specification) spec = specification_figure(r, ov, lower, upper);
    const double value = spec ? spec->value : statistic(*ov.values, r.statistic);
    Judged j = judge(r, ov, limit, value, spec);
    if (spec && !spec->note.empty()) j.note = j.note.empty() ? spec->note : spec->note + "; " + j.note;
    v["value"] = value;
    v["bound"] = j.bound ? json(*j.bound) : json(nullptr);
    v["bound_side"] = r.at_most ? "upper" : "lower";
    v["other_bound"] = j.other ? json(*j.other) : json(nullptr);
    v["samples"] = ov.values->size();
    if (ov.failed > 0) v["failed_samples"] = ov.failed;
    v["verdict"] = j.verdict;
    v["margin"] = r.at_most ? limit - value : value - limit;  // > 0: on the right side of the limit
    if (j.samples_to_decide) v["samples_to_decide"] = *j.samples_to_decide;
    if (!j.note.empty()) v["note"] = j.note;
    if (!j.design_note.empty()) v["design_note"] = j.design_note;
    out.push_back(v);
  }
  return out;
}

}  // namespace poise::engine
