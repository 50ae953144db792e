// The seeker LOS study's own part of summary.json ("details") and of report.html: the LOS
// limit, the shares of units and of the field of regard within it, the pooled field figures,
// the map of p95 over the field and the tolerances sampled. Everything else (answer,
// outputs, sweeps, contributions, sensitivity, convergence, distribution figures,
// provenance) the engine writes as for every kind.
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/format.h"
#include "core/units.h"
#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"
#include "kinds/seeker_los/seeker_field.h"
#include "kinds/seeker_los/seeker_los_sections.h"
#include "kinds/seeker_los/seeker_los_study.h"

namespace poise::kinds::seeker_los {
using namespace poise::model_files;
using namespace poise::engine;
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

json summary_with_unit(const sampling::Summary& s, const std::string& unit, const std::string& description) {
  json j = summary_json(s);
  j["unit"] = unit;
  j["description"] = description;
  return j;
}

// Each tolerance sampled, with its distribution and source.
json seeker_inputs_json(const SeekerModel& model) {
  json inputs = json::array();
  inputs.push_back({{"name", "load_deformation (k')"},
                    {"distribution", model.load_deformation.dist.describe(1.0, "")},
                    {"source", model.load_deformation.source}});
  auto tol_json = [&](const std::string& name, const ToleranceSpec& t) {
    inputs.push_back(
        {{"name", name}, {"distribution", t.dist.describe(t.display_factor, t.display_unit)}, {"source", t.source}});
  };
  tol_json("yaw.perpendicularity (over " + units::format(model.yaw.span, "mm") + "; " +
               model.yaw.tilt_reading.describe() + ")",
           model.yaw.perpendicularity);
  tol_json("pitch.perpendicularity (over " + units::format(model.pitch.span, "mm") + ")", model.pitch.perpendicularity);
  tol_json("optics.axis_error (over " + units::format(model.barrel_length, "mm") + ")", model.optical_axis);
  for (const auto* a : {&model.yaw, &model.pitch}) {
    for (const auto& src : a->bearing_sources) {
      tol_json(std::string(a == &model.yaw ? "yaw." : "pitch.") + src.name + " (per bearing, order " +
                   csv_number(src.order) + (src.load_scaled ? ", x k')" : ")"),
               src.spec);
    }
  }
  return inputs;
}

}  // namespace

json SeekerLosStudy::details(const McResult& mc) const {
  const SeekerLosSections& sec = seeker_sections(config_);
  json d;
  d["requirement"] = {{"as_written", sec.requirement_text},
                      {"arcsec", requirement_rad_ * units::kArcsecPerRad},
                      {"px", requirement_rad_ / model_.pixel_ifov},
                      {"pixel_ifov_arcsec", model_.pixel_ifov * units::kArcsecPerRad},
                      {"pixel_ifov_source", model_.pixel_ifov_source}};
  d["grid"] = {{"yaw_points", sec.yaw_points},
               {"pitch_points", sec.pitch_points},
               {"yaw_deg", {model_.yaw_min / units::kRadPerDeg, model_.yaw_max / units::kRadPerDeg}},
               {"pitch_deg", {model_.pitch_min / units::kRadPerDeg, model_.pitch_max / units::kRadPerDeg}}};
  d["inputs"] = seeker_inputs_json(model_);
  const SeekerFieldFigures* field = field_figures_of(mc);
  if (field && !mc.ok_index.empty()) {
    d["pooled_field_arcsec"] =
        summary_with_unit(field->pooled, "arcsec", "total LOS error over every (sample, grid point)");
  }
  if (mc.outputs.size() == kNumSeekerOutputs) {
    std::size_t meeting = 0;
    const double limit = requirement_rad_ * units::kArcsecPerRad;
    for (double v : mc.values[0]) meeting += v <= limit ? 1 : 0;
    d["fraction_samples_meeting"] = estimate_json(sampling::fraction_wilson(meeting, mc.values[0].size()));
    d["fraction_field_meeting"] = estimate_json(mc.outputs[5].mean);
    d["ci_note"] = "pooled field figures assume independent samples";
  }
  return d;
}

void SeekerLosStudy::report_sections(const McResult& mc, const std::string& plots_dir, bool plots,
                                     std::vector<std::string>& figures, std::ostringstream& h) const {
  const json d = details(mc);
  const json& req = d["requirement"];
  h << "<h2>Units and field within the LOS limit</h2>\n";
  h << "<p>LOS limit: error &le; <b>" << html_escape(req["as_written"].get<std::string>())
    << "</b> = " << significant_or(req["arcsec"].get<double>(), "&ndash;") << " arcsec (pixel IFOV "
    << significant_or(req["pixel_ifov_arcsec"].get<double>(), "&ndash;") << " arcsec; "
    << html_escape(req["pixel_ifov_source"].get<std::string>()) << ").</p>\n";
  if (d.contains("fraction_samples_meeting")) {
    const json& fs_ = d["fraction_samples_meeting"];
    const json& ff = d["fraction_field_meeting"];
    auto pct = [](const json& e) {
      return e.is_number() ? significant_or(100 * e.get<double>(), "&ndash;", 4) : std::string("&ndash;");
    };
    h << "<ul><li>Units that meet it over the <i>whole</i> field of regard: <b>" << pct(fs_["value"])
      << "%</b> <small>(95% "
      << "interval " << pct(fs_["ci95"][0]) << "&ndash;" << pct(fs_["ci95"][1]) << "%)</small></li>"
      << "<li>Share of the field of regard that meets it, averaged over units: <b>" << pct(ff["value"])
      << "%</b> <small>(95% interval " << pct(ff["ci95"][0]) << "&ndash;" << pct(ff["ci95"][1])
      << "%)</small></li></ul>\n";
  }
  if (d.contains("pooled_field_arcsec") && mc.outputs.size() == kNumSeekerOutputs) {
    const double ifov = req["pixel_ifov_arcsec"].get<double>();
    auto row = [&](const std::string& what, double v) {
      h << "<tr><td class='l'>" << what << "</td><td>" << significant_or(v, "&ndash;") << "</td><td>"
        << significant_or(v / ifov, "&ndash;", 3) << "</td></tr>\n";
    };
    h << "<h2>The error over the field of regard</h2>\n<table><tr><th "
         "class='l'>figure</th><th>arcsec</th><th>px</th></tr>\n";
    const json& p = d["pooled_field_arcsec"];
    row("error at a random gimbal angle of a random unit: p50", p["p50"]["value"].get<double>());
    row("error at a random gimbal angle of a random unit: p95", p["p95"]["value"].get<double>());
    row("error at a random gimbal angle of a random unit: p99.73", p["p99_73"]["value"].get<double>());
    row("greatest over the field of a unit: p50", mc.outputs[0].p50.value);
    row("greatest over the field of a unit: p95", mc.outputs[0].p95.value);
    row("greatest over the field of a unit: p99.73", mc.outputs[0].p99_73.value);
    h << "</table>\n<p><small>" << html_escape(d["ci_note"].get<std::string>()) << ".</small></p>\n";
  }
  const SeekerFieldFigures* field = field_figures_of(mc);
  if (plots && field && !field->p95.empty()) {
    std::ostringstream data;
    data << "# yaw_deg pitch_deg p50_arcsec p95_arcsec p99_73_arcsec\n";
    const std::size_t nb = grid_.beta().size();
    for (std::size_t ia = 0; ia < grid_.alpha().size(); ++ia) {
      for (std::size_t ib = 0; ib < nb; ++ib) {
        const std::size_t k = ia * nb + ib;
        data << grid_.alpha()[ia] / units::kRadPerDeg << ' ' << grid_.beta()[ib] / units::kRadPerDeg << ' '
             << field->p50[k] << ' ' << field->p95[k] << ' ' << field->p99_73[k] << '\n';
      }
      data << '\n';
    }
    write_file_atomic((fs::path(plots_dir) / "map.dat").string(), data.str());
    svg_plot(plots_dir, "map_p95",
             "set title 'p95 over units of the total LOS error at each gimbal angle [arcsec]'\n"
             "set xlabel 'yaw [deg]'\nset ylabel 'pitch [deg]'\nset view map\nset pm3d map interpolate 4,4\n" +
                 std::string(kViridisPalette) +
                 "set cblabel 'arcsec'\nsplot 'map.dat' u 1:2:4 with pm3d notitle, "
                 // Each grid point's figures on hover (a small white dot marks where they were computed).
                 "'map.dat' u 1:2:4:(sprintf(\"yaw %g deg, pitch %g deg: p50 %.3g, p95 %.3g, p99.73 %.3g arcsec\", "
                 "$1, $2, $3, $4, $5)) with labels hypertext point pt 7 ps 0.3 lc rgb '#ffffff' notitle\n",
             figures, h);
  }
  h << "<h2>Tolerances sampled</h2>\n<table><tr><th class='l'>input</th><th class='l'>distribution</th>"
       "<th class='l'>source</th></tr>\n";
  for (const auto& i : d["inputs"]) {
    h << "<tr><td class='l'>" << html_escape(i["name"].get<std::string>()) << "</td><td class='l'>"
      << html_escape(i["distribution"].get<std::string>()) << "</td><td class='l'>"
      << html_escape(i["source"].get<std::string>()) << "</td></tr>\n";
  }
  h << "</table>\n";
}

}  // namespace poise::kinds::seeker_los
