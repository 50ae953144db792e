#include "engine/run/procedure_sweeps.h"

#include <cmath>
#include <cstdio>

#include "core/units.h"
#include "engine/report/report_figures.h"
#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"

namespace poise::engine {
namespace {
using nlohmann::json;

// The number and unit of a value as written ("70 mm" -> 70, "mm"): sweep axes in the
// user's own unit, not SI.
std::pair<double, std::string> as_written(const std::string& text) {
  std::size_t used = 0;
  double x = NAN;
  try {
    x = std::stod(text, &used);
  } catch (const std::exception&) {
    return {NAN, ""};
  }
  std::string unit = text.substr(used);
  unit.erase(0, unit.find_first_not_of(' '));
  return {x, unit};
}

}  // namespace

json run_procedure_sweeps(const StudyConfig& cfg, const StudyFactory& make_study, std::size_t run_samples,
                          std::uint64_t seed, int threads, bool progress, const std::vector<Requirement>& requirements,
                          const std::vector<OutputSpec>& outputs) {
  json sweeps = json::array();
  for (const auto& sw : cfg.sweeps) {
    const std::size_t n = sweep_samples(sw, run_samples);
    json js{{"parameter", sw.parameter}, {"samples", n}, {"points", json::array()}};
    for (const auto& v : sw.values) {
      if (progress) std::fprintf(stderr, "  sweep %s = %s: %zu samples\n", sw.parameter.c_str(), v.c_str(), n);
      StudyConfig c = cfg;
      auto overrides = c.overrides;
      overrides[sw.parameter] = v;
      c.overrides = apply_study_overrides(c, overrides);
      const std::unique_ptr<ProcedureStudy> study = make_study(c, n, seed);
      const McResult mc = study->run(threads, false, nullptr, {});
      json p{{"value", v}, {"value_si", units::parse_quantity(v).value}, {"samples", mc.completed},
             {"failures", mc.failures}};
      p["outputs"] = outputs_json(mc, outputs, false);
      p["requirements"] = judge_requirements(requirements, outputs, requirement_values(mc, outputs, cfg));
      js["points"].push_back(p);
    }
    sweeps.push_back(js);
  }
  return sweeps;
}

std::string sweeps_html(const json& sweeps, const std::vector<OutputSpec>& outputs, const std::filesystem::path& plots_dir,
                        bool plots) {
  if (!sweeps.is_array() || sweeps.empty()) return "";
  std::string h = "<h2>Sweeps</h2>\n<p>Each value runs the same samples (common random numbers): the differences "
                  "between values are the design's, not the sampling's. Intervals are 95%.</p>\n";
  for (std::size_t s = 0; s < sweeps.size(); ++s) {
    const json& sw = sweeps[s];
    const std::string param = sw["parameter"].get<std::string>();
    const std::string x_unit =
        as_written(sw["points"].empty() ? std::string() : sw["points"][0]["value"].get<std::string>()).second;
    // The outputs shown: those a requirement names (with its statistic), else the first two.
    const auto show =
        shown_statistics(sw["points"].empty() ? json::array() : sw["points"][0]["requirements"], outputs, 2);
    h += "<h3>" + html_escape(param) + "</h3>\n<table><tr><th>" + html_escape(param) + "</th>";
    for (const auto& [name, stat] : show) h += "<th>" + html_escape(stat + " of " + name) + "</th>";
    h += "<th>failed</th></tr>\n";
    for (const auto& p : sw["points"]) {
      h += "<tr><td>" + html_escape(p["value"].get<std::string>()) + "</td>";
      for (const auto& [name, stat] : show) {
        std::string cell = "&ndash;";
        if (p["outputs"].contains(name) && p["outputs"][name].contains(stat)) {
          const json& e = p["outputs"][name][stat];
          cell = format_significant(e["value"].get<double>()) + " " + html_escape(p["outputs"][name]["unit"].get<std::string>());
          if (e["ci95"][0].is_number() && e["ci95"][1].is_number()) {
            cell += " <small>[" + format_significant(e["ci95"][0].get<double>()) + ", " +
                    format_significant(e["ci95"][1].get<double>()) + "]</small>";
          }
        }
        for (const auto& r : p["requirements"]) {
          if (r["output"] == name && r["statistic"] == stat) cell += " <b>" + html_escape(r["verdict"].get<std::string>()) + "</b>";
        }
        h += "<td>" + cell + "</td>";
      }
      h += "<td>" + std::to_string(p["failures"].get<std::size_t>()) + "</td></tr>\n";
    }
    h += "</table>\n";
    if (!plots) continue;
    std::vector<std::string> figures;
    std::string why;
    for (std::size_t k = 0; k < show.size(); ++k) {
      const auto& [name, stat] = show[k];
      std::vector<SweepFigurePoint> pts;
      std::string unit;
      for (const auto& p : sw["points"]) {
        if (!p["outputs"].contains(name) || !p["outputs"][name].contains(stat)) continue;
        const json& e = p["outputs"][name][stat];
        unit = p["outputs"][name]["unit"].get<std::string>();
        pts.push_back({as_written(p["value"].get<std::string>()).first, e["value"].get<double>(),
                       e["ci95"][0].is_number() ? e["ci95"][0].get<double>() : NAN,
                       e["ci95"][1].is_number() ? e["ci95"][1].get<double>() : NAN});
      }
      std::vector<FigureLine> limits;
      if (!sw["points"].empty()) {
        for (const auto& r : sw["points"][0]["requirements"]) {
          if (r["output"] == name && r["statistic"] == stat) {
            limits.push_back({r["limit"]["value"].get<double>(),
                              std::string(r["at_most"].get<bool>() ? "at most " : "at least ") +
                                  r["limit"]["as_written"].get<std::string>(),
                              "#cc3311"});
          }
        }
      }
      const std::string label = stat + " of " + name + (unit.empty() || unit == "1" ? "" : " [" + unit + "]");
      sweep_figure(plots_dir, "sweep" + std::to_string(s) + "_" + name + "_" + stat, label + " against " + param,
                   param + (x_unit.empty() ? "" : " [" + x_unit + "]"), label, pts, limits, figures, why);
    }
    h += figures_html(plots_dir, figures);
    if (!why.empty()) h += "<p><small>" + html_escape(why) + "</small></p>\n";
  }
  return h;
}

}  // namespace poise::engine
