#pragma once
/// The figures of the geometry kinds' own report sections (geometry_mass_properties,
/// los_obstruction): gnuplot scripts with their data beside them in plots/, SVG figures set
/// inline with their captions. The engine writes the rest of the report as for every kind.
#include <filesystem>
#include <string>
#include <vector>

namespace poise::geometry_studies {

struct GeometryPlot {
  std::string name;    ///< file stem: plots/<name>.dat, .gp, .svg
  std::string data;    ///< contents of <name>.dat
  std::string script;  ///< gnuplot commands after the terminal and output lines
  std::string caption;
};

/// Writes each plot's data and script into `plots_dir`, runs gnuplot and returns the figures
/// inline with their captions (HTML); a plot gnuplot could not make leaves a note instead.
std::string geometry_figures_html(const std::filesystem::path& plots_dir, const std::vector<GeometryPlot>& plots);

/// A histogram script for one column of a .dat file (for GeometryPlot::script): about
/// sqrt(n) bins (5 to 40), each box as wide as its bin.
std::string histogram_script(const std::string& dat, int column, const std::string& title, const std::string& xlabel);

}  // namespace poise::geometry_studies
