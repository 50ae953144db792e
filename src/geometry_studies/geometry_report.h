#pragma once
/// Plots and report.html of the geometry studies (geometry_mass_properties, los_obstruction):
/// gnuplot scripts with their data beside them in plots/, SVG figures, and a report with
/// the study's notes, tables (given as HTML) and every output's statistics.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace poise::studies {

struct GeometryPlot {
  std::string name;    ///< file stem: plots/<name>.dat, .gp, .svg
  std::string data;    ///< contents of <name>.dat
  std::string script;  ///< gnuplot commands after the terminal and output lines
  std::string caption;
};

struct GeometryReport {
  std::string dir;                 ///< run folder
  const nlohmann::json& summary;   ///< summary.json; "outputs" are tabulated
  std::vector<std::string> tables; ///< HTML fragments, in order, after the verdict
  std::vector<GeometryPlot> plots;
  bool make_plots = true;
  std::vector<std::string> figures;  ///< SVGs already made in plots/ (inline first)
};

/// Writes plots/ and report.html; a missing gnuplot is noted, not an error.
void write_geometry_report(const GeometryReport& r);

/// A histogram script for one column of a .dat file (for GeometryPlot::script).
std::string histogram_script(const std::string& dat, int column, const std::string& title, const std::string& xlabel);

}  // namespace poise::studies
