#include "geometry_studies/geometry_plots.h"

#include <sstream>

#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"

namespace poise::geometry_studies {
using namespace poise::engine;
namespace fs = std::filesystem;

std::string geometry_figures_html(const fs::path& plots_dir, const std::vector<GeometryPlot>& plots) {
  std::ostringstream notes;
  std::string html;
  for (const auto& p : plots) {
    write_file_atomic((plots_dir / (p.name + ".dat")).string(), p.data);
    std::vector<std::string> made;
    if (svg_plot(plots_dir, p.name, p.script, made, notes)) html += inline_svg(plots_dir / made.back(), p.caption);
  }
  return html + notes.str();
}

std::string histogram_script(const std::string& dat, int column, const std::string& title, const std::string& xlabel) {
  std::ostringstream g;
  g << "set title '" << title << "'\nset xlabel '" << xlabel << "'\nset ylabel 'samples'\n"
    << "stats '" << dat << "' u " << column << " nooutput\n"
    << "nb = ceil(sqrt(STATS_records)); nb = (nb < 5 ? 5 : (nb > 40 ? 40 : nb))\n"
    << "bw = (STATS_max - STATS_min) / nb\nif (bw <= 0) bw = (abs(STATS_max) > 0 ? abs(STATS_max) * 1e-3 : 1e-9)\n"
    << "bin(x) = bw * floor(x / bw) + bw / 2\nset boxwidth bw absolute\nset yrange [0:*]\nset style fill solid 0.6\n"
    << "if (STATS_records <= 10) set ytics 1\n"  // whole samples, not 0.5
    << "plot '" << dat << "' u (bin($" << column << ")):(1.0) smooth freq with boxes lc rgb '#4477aa' notitle\n";
  return g.str();
}

}  // namespace poise::geometry_studies
