#include "engine/results/references.h"

#include "core/nearest_name.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/format.h"
#include "core/units.h"
#include "engine/kind_interface/study_kind.h"
#include "engine/results/result_io.h"
#include "engine/study_files/model_overrides.h"
#include "engine/study_files/toml_reader.h"

namespace poise::engine {
namespace {
using nlohmann::json;

// "sample", or a figure of the summary (sampling/statistics.h).
const std::vector<std::string> kStatistics = [] {
  std::vector<std::string> names = {"sample", "mean", "std", "min"};
  for (const sampling::SummaryQuantile& q : sampling::summary_quantiles()) names.emplace_back(q.name);
  names.emplace_back("max");
  return names;
}();

}  // namespace

std::vector<ReferenceFigure> read_references(TomlReader& root) {
  std::vector<ReferenceFigure> out;
  for (auto& t : root.table_array("reference")) {
    ReferenceFigure r;
    r.file = t.context().file;
    r.line = t.line_of("output") > 0 ? t.line_of("output") : t.line_of("value");
    r.name = t.string("name");
    r.output = t.string("output", r.name);
    r.statistic = t.choice("statistic", kStatistics, "sample");
    r.value_text = t.string("value");
    if (!r.value_text.empty()) {
      try {
        r.value_si = units::parse_quantity(r.value_text).value;
      } catch (const Error& e) {
        t.error("value", quote_value(r.value_text),
                std::string("a number with the unit of the output, e.g. \"0.78 mN*m\" (") + e.what() + ")");
      }
    }
    r.source = t.string("source");
    r.role = t.choice("role", {"validation", "calibration_target"});
    r.follows_from = t.string("follows_from", "");
    if (r.role == "calibration_target" && r.follows_from.empty() && t.has("role")) {
      t.error("follows_from", "", "what was calibrated to this figure (a calibration target must say it)");
    }
    if (t.has("tolerance")) {
      const std::string tol = t.string("tolerance");
      double v = -1;
      if (tol.size() > 1 && tol.back() == '%') {
        try {
          v = std::stod(tol.substr(0, tol.size() - 1)) / 100.0;
        } catch (const std::exception&) {
          v = -1;
        }
      }
      if (!(v >= 0 && v < 10)) {
        t.error("tolerance", quote_value(tol), "a share of the reference, e.g. \"5%\"");
      } else {
        r.tolerance_relative = v;
      }
    }
    t.string("notes", "");
    out.push_back(r);
  }
  return out;
}

std::vector<ReferenceFigure> read_model_references(const std::string& model_path) {
  ModelDocument m = open_model_file(model_path, {});
  TomlReader root(m.doc, m.ctx);
  std::vector<ReferenceFigure> refs = read_references(root);
  if (!m.ctx->errors.empty()) throw ValidationError(m.ctx->errors);
  return refs;
}

std::vector<ReferenceFigure> declared_references(const StudyConfig& cfg, const std::vector<OutputSpec>& outputs) {
  std::vector<ReferenceFigure> refs = cfg.references;
  if (!cfg.model_path.empty()) {
    for (auto& r : read_model_references(cfg.model_path)) refs.push_back(r);
  }
  std::vector<InputError> errors;
  for (const auto& r : refs) {
    const auto it =
        std::find_if(outputs.begin(), outputs.end(), [&](const OutputSpec& o) { return o.name == r.output; });
    if (it == outputs.end()) {
      std::string names;
      for (const auto& o : outputs) names += (names.empty() ? "" : ", ") + o.name;
      errors.emplace_back(SourceLocation{r.file, r.line, 0}, "reference.output", quote_value(r.output),
                          "an output of this study: " + names + did_you_mean(r.output, output_names_of(outputs)));
      continue;
    }
    try {
      const units::Quantity u = unit_quantity(it->unit), v = units::parse_quantity(r.value_text);
      if (!(u.dim == v.dim)) {
        errors.emplace_back(SourceLocation{r.file, r.line, 0}, "reference.value", quote_value(r.value_text),
                            "a value in a unit of " + units::dimension_name(u.dim) + " (the output " + r.output +
                                " is in " + (it->unit.empty() ? std::string("no unit") : it->unit) + ")");
      }
    } catch (const Error&) {
      // A unit the reader cannot parse was reported when the file was read.
    }
  }
  if (!errors.empty()) throw ValidationError(errors);
  return refs;
}

json compare_references(const std::vector<ReferenceFigure>& refs, const std::vector<OutputSpec>& outputs,
                        const json& outputs_json,
                        const std::function<const std::vector<double>*(const std::string&)>& values) {
  json out = json::array();
  for (const auto& r : refs) {
    const auto it =
        std::find_if(outputs.begin(), outputs.end(), [&](const OutputSpec& o) { return o.name == r.output; });
    if (it == outputs.end() || !outputs_json.contains(r.output)) continue;
    const double in_unit = r.value_si / unit_quantity(it->unit).value;
    json c{{"name", r.name},     {"output", r.output},   {"statistic", r.statistic},
           {"unit", it->unit},   {"reference", in_unit}, {"reference_as_written", r.value_text},
           {"source", r.source}, {"role", r.role},       {"declared_in", r.file + ":" + std::to_string(r.line)}};
    if (!r.follows_from.empty()) c["follows_from"] = r.follows_from;
    const json& o = outputs_json[r.output];
    bool agrees = false;
    if (r.statistic == "sample") {
      const std::vector<double>* v = values(r.output);
      if (!v || v->empty()) continue;
      std::size_t below = 0;
      for (double x : *v) below += x <= in_unit ? 1 : 0;
      const double pct = static_cast<double>(below) / static_cast<double>(v->size());
      c["percentile"] = pct;
      agrees = pct >= 0.025 && pct <= 0.975;
      c["rule"] = "agrees when the reference lies within the central 95% of the simulated distribution";
      if (v->size() < 40 && r.role == "validation") {
        // Fewer than 40 samples cannot place the 2.5% and 97.5% points: no verdict.
        c["verdict"] = "undecided";
        c["why"] = std::to_string(v->size()) + " samples cannot resolve the central 95% (40 or more needed)";
        out.push_back(c);
        continue;
      }
    } else {
      const json& e = o[r.statistic];
      c["simulated"] = e;
      const double val = e["value"].is_number() ? e["value"].get<double>() : NAN;
      const double lo =
          e["ci95"][0].is_number() ? e["ci95"][0].get<double>() : -std::numeric_limits<double>::infinity();
      const double hi = e["ci95"][1].is_number() ? e["ci95"][1].get<double>() : std::numeric_limits<double>::infinity();
      agrees = (in_unit >= lo && in_unit <= hi) ||
               (r.tolerance_relative > 0 && std::abs(val - in_unit) <= r.tolerance_relative * std::abs(in_unit));
      c["rule"] = r.tolerance_relative > 0
                      ? "agrees when the reference lies in the 95% interval of the simulated " + r.statistic +
                            " or within " + significant_or(100 * r.tolerance_relative, "&ndash;", 3) + "% of it"
                      : "agrees when the reference lies in the 95% interval of the simulated " + r.statistic;
    }
    c["verdict"] = r.role == "calibration_target" ? "calibration_target" : agrees ? "agrees" : "disagrees";
    out.push_back(c);
  }
  return out;
}

}  // namespace poise::engine
