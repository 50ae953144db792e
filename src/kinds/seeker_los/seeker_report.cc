#include "kinds/seeker_los/seeker_report.h"
#include "engine/references.h"
#include "engine/requirements.h"
#include "engine/report_figures.h"
#include "engine/report_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/units.h"
#include "engine/convergence.h"
#include "engine/result_io.h"
#include "engine/sensitivity_output.h"

namespace poise::studies {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

std::string num(double v, int prec = 4) {
  if (!std::isfinite(v)) return "&ndash;";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

std::string num_json(const json& j, int prec = 4) {
  return j.is_number() ? num(j.get<double>(), prec) : std::string("&ndash;");
}


std::string with_ci(const json& e, int prec = 4) {
  return num_json(e["value"], prec) + " <small>[" + num_json(e["ci95"][0], prec) + ", " +
         num_json(e["ci95"][1], prec) + "]</small>";
}

void write_file(const fs::path& p, const std::string& text) { write_file_atomic(p.string(), text); }

}  // namespace

void write_report(const ReportInputs& in) {
  const json& s = in.summary;
  const fs::path dir(in.dir);
  const fs::path pdir = dir / "plots";
  fs::create_directories(pdir);
  const double req = s["requirement"]["arcsec"].get<double>();
  std::vector<std::string> figures;  // (svg file names)
  std::string plot_note;

  if (in.plots && !in.mc.values.empty()) {
    // Data.
    {
      std::ostringstream d;
      d << "# yaw_deg pitch_deg p50_arcsec p95_arcsec p99_73_arcsec\n";
      const std::size_t nb = in.beta.size();
      for (std::size_t ia = 0; ia < in.alpha.size(); ++ia) {
        for (std::size_t ib = 0; ib < nb; ++ib) {
          const std::size_t k = ia * nb + ib;
          d << in.alpha[ia] / units::kRadPerDeg << ' ' << in.beta[ib] / units::kRadPerDeg << ' '
            << in.mc.map_p50[k] << ' ' << in.mc.map_p95[k] << ' ' << in.mc.map_p99_73[k] << '\n';
        }
        d << '\n';
      }
      write_file(pdir / "map.dat", d.str());
    }
    const std::string head = "set terminal svg size 760,480 dynamic noenhanced font 'Helvetica,12'\n";
    std::ostringstream map;
    map << head << "set output 'map_p95.svg'\n"
        << "set title 'p95 over samples of the total LOS error at each gimbal angle [arcsec]'\n"
        << "set xlabel 'yaw [deg]'\nset ylabel 'pitch [deg]'\nset view map\nset pm3d map interpolate 4,4\n"
        << kViridisPalette << "set cblabel 'arcsec'\n"
        << "splot 'map.dat' u 1:2:4 with pm3d notitle\n";
    write_file(pdir / "map_p95.gp", map.str());
    std::vector<std::string> scripts = {"map_p95"};
    // Sweeps.
    int si = 0;
    for (const auto& sw : s["sweeps"]) {
      const std::string base = "sweep_" + std::to_string(si++);
      std::ostringstream d;
      d << "# " << sw["parameter"].get<std::string>()
        << " value_si value_as_written | p50 p95 p95_lo p95_hi p99_73 of los_max [arcsec]\n";
      for (const auto& p : sw["points"]) {
        if (!p.contains("los_max_arcsec")) continue;
        const auto& l = p["los_max_arcsec"];
        auto end = [&](const json& e, int k) { return e["ci95"][k].is_number() ? e["ci95"][k] : e["value"]; };
        d << p["value_si"].get<double>() << " \"" << p["value"].get<std::string>() << "\" " << num_json(l["p50"]["value"], 8)
          << ' ' << num_json(l["p95"]["value"], 8) << ' ' << num_json(end(l["p95"], 0), 8) << ' '
          << num_json(end(l["p95"], 1), 8) << ' ' << num_json(l["p99_73"]["value"], 8) << '\n';
      }
      write_file(pdir / (base + ".dat"), d.str());
      std::ostringstream g;
      g << head << "set output '" << base << ".svg'\n"
        << "set title 'Greatest LOS error over the field vs " << sw["parameter"].get<std::string>() << "'\n"
        << "set xlabel '" << sw["parameter"].get<std::string>() << " [SI]'\nset ylabel 'arcsec'\nset grid\n"
        << "set key outside bottom center horizontal\nset yrange [0:*]\n"
        << "plot '" << base << ".dat' u 1:5:6 with filledcurves lc rgb '#bbccee' t 'p95, 95% interval', "
        << "'' u 1:3 w lp lw 2 t 'MC p50', '' u 1:4 w lp lw 2 t 'MC p95', '' u 1:7 w lp lw 2 t 'MC p99.73', "
        << req << " w l lc rgb '#cc3311' lw 2 t 'requirement'\n";
      write_file(pdir / (base + ".gp"), g.str());
      scripts.push_back(base);
    }
    // The distribution of the main output with the requirement and declared references as lines.
    if (!in.mc.values.empty()) {
      std::vector<FigureLine> lines{{req, "requirement", "#cc3311"}};
      for (const auto& c : s.value("references", json::array())) {
        if (c["output"] == "los_max_arcsec") lines.push_back({c["reference"].get<double>(), c["name"].get<std::string>(), "#999999"});
      }
      std::string why;
      if (!distribution_figures(pdir, "los_max_arcsec", "arcsec", in.mc.values[0], in.mc.ok_index, lines, figures, why)) {
        plot_note = why;
      }
    }
    if (s.contains("contributions") && s["contributions"].size() > 1) {
      const double base_p95 = s["contributions"][0]["stats"]["los_max_p95"].get<double>();
      std::vector<std::pair<std::string, double>> bars;
      for (std::size_t i = 1; i < s["contributions"].size(); ++i) {
        const auto& c = s["contributions"][i];
        bars.emplace_back(c["without"].get<std::string>(), base_p95 - c["stats"]["los_max_p95"].get<double>());
      }
      std::stable_sort(bars.begin(), bars.end(), [](const auto& x, const auto& y) { return std::abs(x.second) > std::abs(y.second); });
      std::string why;
      if (!tornado_figure(pdir, "contributions", "Which tolerance drives the error: drop of p95 with it set to zero",
                          "drop of p95 of the greatest LOS error [arcsec]", bars, figures, why)) {
        plot_note = why;
      }
    }
    if (s.contains("sensitivity")) {
      std::string why;
      if (!sensitivity_tornado(pdir, s["sensitivity"], "los_max_arcsec", figures, why)) plot_note = why;
    }
    for (const auto& sc : scripts) {
      std::string why;
      if (run_gnuplot((pdir / (sc + ".gp")).string(), &why)) {
        figures.push_back(sc + ".svg");
      } else {
        plot_note = why;
      }
    }
  } else if (!in.plots) {
    plot_note = "plots were switched off for this run";
  }

  // ---- report.html
  std::ostringstream h;
  const auto& st = s["study"];
  h << report_page_head(st["name"].get<std::string>());
  h << "<h1>" << html_escape(st["title"].get<std::string>().empty() ? st["name"].get<std::string>()
                                                           : st["title"].get<std::string>())
    << "</h1>\n" << answer_html(s.value("answer", std::string()), s.value("requirements", json::array())) << "<p>Study <code>" << html_escape(st["file"].get<std::string>()) << "</code>, model <code>"
    << html_escape(st["model_file"].get<std::string>()) << "</code> (" << html_escape(st["model_source"].get<std::string>())
    << ").</p>\n";

  if (s.value("status", "complete") != "complete") {
    h << "<p class='bad'><b>This run is " << html_escape(s["status"].get<std::string>()) << "</b>: "
      << html_escape(s.value("stop_reason", std::string("stopped by a signal"))) << ". The figures cover the "
      << s["sampling"]["samples"].get<std::size_t>() << " samples that ran.</p>\n";
  }
  // Verdict.
  const auto& req_j = s["requirement"];
  h << "<h2>Units and field within the LOS limit</h2>\n";
  if (s.contains("fraction_samples_meeting")) {
    const auto& fs_ = s["fraction_samples_meeting"];
    const auto& ff = s["fraction_field_meeting"];
    const auto& lm = s["outputs"]["los_max_arcsec"];
    h << "<p>Requirement: LOS error &le; <b>" << html_escape(req_j["as_written"].get<std::string>()) << "</b> = "
      << num(req_j["arcsec"].get<double>()) << " arcsec (pixel IFOV " << num(req_j["pixel_ifov_arcsec"].get<double>())
      << " arcsec; " << html_escape(req_j["pixel_ifov_source"].get<std::string>()) << ").</p>\n<ul>"
      << "<li>Fraction of samples (units) that meet it over the <i>whole</i> field of regard: <b>"
      << num(100 * fs_["value"].get<double>(), 4) << "%</b> <small>(95% CI " << num(100 * fs_["ci95"][0].get<double>(), 4)
      << "&ndash;" << num(100 * fs_["ci95"][1].get<double>(), 4) << "%)</small></li>"
      << "<li>Fraction of the field of regard that meets it, averaged over samples: <b>"
      << num(100 * ff["value"].get<double>(), 4) << "%</b> <small>(95% CI " << num_json(ff["ci95"][0].is_number() ? json(100 * ff["ci95"][0].get<double>()) : json(nullptr))
      << "&ndash;" << num_json(ff["ci95"][1].is_number() ? json(100 * ff["ci95"][1].get<double>()) : json(nullptr)) << "%)</small></li>"
      << "<li>Greatest LOS error over the field: p50 " << num_json(lm["p50"]["value"]) << ", p95 "
      << num_json(lm["p95"]["value"]) << ", p99.73 " << num_json(lm["p99_73"]["value"]) << " arcsec.</li></ul>\n";
  }
  if (s["failures"]["count"].get<std::size_t>() > 0) {
    h << "<p class='bad'>" << s["failures"]["count"].get<std::size_t>()
      << " sample(s) failed; their reasons are in samples.csv and summary.json.</p>\n";
  }

  h << references_html(s.value("references", json::array()));

  // The Monte Carlo's figures in arcsec and pixels (a budget of the design is checked beside
  // them with `poise budget`).
  const double ifov = req_j["pixel_ifov_arcsec"].get<double>();
  auto row = [&](const std::string& what, double v) {
    h << "<tr><td class='l'>" << what << "</td><td>" << num(v) << "</td><td>" << num(v / ifov, 3)
      << "</td></tr>\n";
  };
  h << "<h2>Monte Carlo figures</h2>\n<table><tr><th class='l'>figure</th><th>arcsec</th><th>px</th></tr>\n";
  if (s.contains("pooled_field_arcsec")) {
    const auto& p = s["pooled_field_arcsec"];
    row("MC, error at a random gimbal angle of a random unit: p50", p["p50"]["value"].get<double>());
    row("MC, error at a random gimbal angle of a random unit: p95", p["p95"]["value"].get<double>());
    row("MC, error at a random gimbal angle of a random unit: p99.73", p["p99_73"]["value"].get<double>());
    const auto& lm = s["outputs"]["los_max_arcsec"];
    row("MC, greatest over the field of a unit: p50", lm["p50"]["value"].get<double>());
    row("MC, greatest over the field of a unit: p95", lm["p95"]["value"].get<double>());
    row("MC, greatest over the field of a unit: p99.73", lm["p99_73"]["value"].get<double>());
  }
  h << "</table>\n";
  // Contributions.
  if (s.contains("contributions") && s["contributions"].size() > 1) {
    const auto& c = s["contributions"];
    const auto& base = c[0]["stats"];
    h << "<h2>Which tolerance drives the error</h2>\n<p>The study re-run with one tolerance set "
         "to zero at a time (" << c[0]["samples"].get<std::size_t>() << " samples, the same random "
         "numbers), so the drop is that tolerance's share of the error.</p>\n<table><tr><th class='l'>"
         "tolerance set to zero</th><th>greatest over field p50</th><th>p95</th><th>drop of p95</th>"
         "<th>p99.73</th><th>units meeting</th></tr>\n";
    for (const auto& row_j : c) {
      const auto& st_ = row_j["stats"];
      h << "<tr><td class='l'>" << html_escape(row_j["without"].get<std::string>()) << "</td><td>"
        << num(st_["los_max_p50"].get<double>()) << "</td><td>" << num(st_["los_max_p95"].get<double>())
        << "</td><td>" << num(base["los_max_p95"].get<double>() - st_["los_max_p95"].get<double>(), 3)
        << "</td><td>" << num(st_["los_max_p99_73"].get<double>()) << "</td><td>"
        << num(100 * st_["fraction_samples_meeting"].get<double>(), 4) << "%</td></tr>\n";
    }
    h << "</table>\n<p><small>arcsec, greatest total LOS error over the field of regard.</small></p>\n";
  }

  if (s.contains("sensitivity")) h << sensitivity_html(s["sensitivity"]);

  // Figures.
  h << "<h2>Figures</h2>\n";
  if (!plot_note.empty()) h << "<p class='bad'>" << html_escape(plot_note) << "</p>\n";
  h << figures_html(pdir, figures);

  // Outputs.
  h << "<h2>Per-sample outputs</h2>\n<p><small>value [95% confidence interval]; a missing end needs "
       "more samples. " << html_escape(s["sampling"]["ci_note"].get<std::string>()) << ".</small></p>\n"
    << "<table><tr><th class='l'>output</th><th class='l'>unit</th><th>mean</th><th>std</th><th>p50</th>"
       "<th>p95</th><th>p99.73</th><th>max</th></tr>\n";
  for (const auto& [name, o] : s["outputs"].items()) {
    h << "<tr><td class='l'><code>" << html_escape(name) << "</code><br><small>" << html_escape(o["description"].get<std::string>())
      << "</small></td><td class='l'>" << html_escape(o["unit"].get<std::string>()) << "</td><td>" << with_ci(o["mean"])
      << "</td><td>" << with_ci(o["std"]) << "</td><td>" << with_ci(o["p50"]) << "</td><td>" << with_ci(o["p95"])
      << "</td><td>" << with_ci(o["p99_73"]) << "</td><td>" << with_ci(o["max"]) << "</td></tr>\n";
  }
  h << "</table>\n";
  if (s.contains("sample_convergence")) h << convergence_html(s["sample_convergence"]);

  // Sweeps.
  for (const auto& sw : s["sweeps"]) {
    h << "<h2>Sweep of <code>" << html_escape(sw["parameter"].get<std::string>()) << "</code></h2>\n<p>"
      << sw["samples"].get<std::size_t>() << " samples per value, same seed at every value (common random "
         "numbers).</p>\n<table><tr><th class='l'>value</th><th>MC p50</th><th>MC p95</th><th>MC p99.73</th>"
         "<th>samples meeting</th></tr>\n";
    for (const auto& p : sw["points"]) {
      if (!p.contains("los_max_arcsec")) continue;
      const auto& l = p["los_max_arcsec"];
      h << "<tr><td class='l'>" << html_escape(p["value"].get<std::string>()) << "</td><td>" << num_json(l["p50"]["value"])
        << "</td><td>" << num_json(l["p95"]["value"]) << "</td><td>" << num_json(l["p99_73"]["value"]) << "</td><td>"
        << num(100 * p["fraction_samples_meeting"]["value"].get<double>(), 4) << "%</td>";
      h << "</tr>\n";
    }
    h << "</table>\n<p><small>arcsec, greatest LOS error over the field of regard.</small></p>\n";
  }

  // Inputs.
  h << "<h2>Tolerances sampled</h2>\n<table><tr><th class='l'>input</th><th class='l'>distribution</th>"
       "<th class='l'>source</th></tr>\n";
  for (const auto& i : s["sampling"]["inputs"]) {
    h << "<tr><td class='l'>" << html_escape(i["name"].get<std::string>()) << "</td><td class='l'>"
      << html_escape(i["distribution"].get<std::string>()) << "</td><td class='l'>" << html_escape(i["source"].get<std::string>())
      << "</td></tr>\n";
  }
  h << "</table>\n";
  if (!st["notes"].get<std::string>().empty()) {
    h << "<h2>Notes of the study</h2>\n<pre>" << html_escape(st["notes"].get<std::string>()) << "</pre>\n";
  }
  h << provenance_html(s["provenance"])
    << "<p><small>Files: samples.csv (one row per sample), summary.json, plots/ (data, gnuplot "
       "scripts, SVG).</small></p>\n</body></html>\n";
  write_file(dir / "report.html", h.str());
}

}  // namespace poise::studies
