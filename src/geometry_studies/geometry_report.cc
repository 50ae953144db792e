#include "geometry_studies/geometry_report.h"

#include <fstream>
#include <sstream>

#include "engine/report_plot.h"
#include "engine/requirements.h"
#include "engine/result_io.h"

namespace poise::studies {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string cell(const json& e) {
  if (!e.is_object() || !e.contains("value") || e["value"].is_null()) return "<td>-</td>";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", e["value"].get<double>());
  return std::string("<td>") + buf + "</td>";
}

}  // namespace

std::string histogram_script(const std::string& dat, int column, const std::string& title, const std::string& xlabel) {
  std::ostringstream g;
  g << "set title '" << title << "'\nset xlabel '" << xlabel << "'\nset ylabel 'samples'\n"
    << "stats '" << dat << "' u " << column << " nooutput\n"
    // About sqrt(n) bins (5 to 40), each box as wide as its bin.
    << "nb = ceil(sqrt(STATS_records)); nb = (nb < 5 ? 5 : (nb > 40 ? 40 : nb))\n"
    << "bw = (STATS_max - STATS_min) / nb\nif (bw <= 0) bw = (abs(STATS_max) > 0 ? abs(STATS_max) * 1e-3 : 1e-9)\n"
    << "bin(x) = bw * floor(x / bw) + bw / 2\nset boxwidth bw absolute\nset yrange [0:*]\nset style fill solid 0.6\nset grid\n"
    << "plot '" << dat << "' u (bin($" << column << ")):(1.0) smooth freq with boxes lc rgb '#4477aa' notitle\n";
  return g.str();
}

void write_geometry_report(const GeometryReport& r) {
  const json& s = r.summary;
  const fs::path dir(r.dir), pdir = dir / "plots";
  std::vector<std::pair<std::string, std::string>> figures;  // (svg, caption)
  for (const auto& f : r.figures) figures.emplace_back(f, "");
  std::string plot_note;
  if (r.make_plots && !r.plots.empty()) {
    fs::create_directories(pdir);
    for (const auto& p : r.plots) {
      write_file_atomic((pdir / (p.name + ".dat")).string(), p.data);
      write_file_atomic((pdir / (p.name + ".gp")).string(),
                        "set terminal svg size 760,480 dynamic noenhanced font 'Helvetica,12'\nset output '" + p.name +
                            ".svg'\n" + p.script);
      std::string why;
      if (run_gnuplot((pdir / (p.name + ".gp")).string(), &why)) {
        figures.emplace_back(p.name + ".svg", p.caption);
      } else {
        plot_note = why;
      }
    }
  } else if (!r.make_plots) {
    plot_note = "plots were switched off for this run";
  }
  std::ostringstream h;
  const auto& st = s["study"];
  const std::string title = st.value("title", "").empty() ? st.value("name", "") : st.value("title", "");
  h << report_page_head(st.value("name", ""))
    << "<h1>" << html_escape(title) << "</h1>\n"
    << answer_html(s.value("answer", std::string()), s.value("requirements", json::array())) << "<p>Study <code>"
    << html_escape(st.value("file", "")) << "</code>, model <code>" << html_escape(st.value("model_file", ""))
    << "</code> (" << html_escape(st.value("model_source", "")) << ").</p>\n";
  if (!st.value("notes", "").empty()) h << "<pre>" << html_escape(st.value("notes", "")) << "</pre>\n";
  for (const auto& t : r.tables) h << t << '\n';
  h << "<h2>Per-sample outputs</h2>\n<table><tr><th class='l'>output</th><th>unit</th><th>mean</th><th>std</th>"
    << "<th>p50</th><th>p95</th><th>p99.73</th><th>max</th><th class='l'>what</th></tr>\n";
  if (s.contains("outputs")) {
    for (const auto& [name, o] : s["outputs"].items()) {
      h << "<tr><td class='l'>" << html_escape(name) << "</td><td>" << html_escape(o.value("unit", "")) << "</td>"
        << cell(o["mean"]) << cell(o["std"]) << cell(o["p50"]) << cell(o["p95"]) << cell(o["p99_73"]) << cell(o["max"])
        << "<td class='l'>" << html_escape(o.value("description", "")) << "</td></tr>\n";
    }
  }
  h << "</table>\n<p><small>Samples: " << s["sampling"].value("samples", 0) << " ("
    << html_escape(s["sampling"].value("method", "")) << ", seed " << s["sampling"].value("seed", 0)
    << "); failures: " << s["failures"].value("count", 0) << ". Every sample is in samples.csv; "
    << "<code>poise replay</code> recomputes one alone.</small></p>\n";
  if (!figures.empty()) h << "<h2>Figures</h2>\n";
  for (const auto& [svg, caption] : figures) {
    h << inline_svg(dir / "plots" / svg, caption);
  }
  if (!plot_note.empty()) h << "<p><small>" << html_escape(plot_note) << "</small></p>\n";
  h << provenance_html(s["provenance"]) << "</body></html>\n";
  write_file_atomic((dir / "report.html").string(), h.str());
}

}  // namespace poise::studies
