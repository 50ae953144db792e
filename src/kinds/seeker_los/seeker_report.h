#pragma once
/// Plots (gnuplot, headless SVG) and report.html of a LOS study run.
#include <nlohmann/json.hpp>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "kinds/seeker_los/seeker_los_study.h"
#include "engine/report_plot.h"

namespace poise::studies {

struct ReportInputs {
  std::string dir;                 ///< run folder
  const nlohmann::json& summary;   ///< what summary.json holds
  const SeekerMcResult& mc;
  const std::vector<double>& alpha;  ///< grid, rad
  const std::vector<double>& beta;
  bool plots = true;
};

/// Writes plots/ (data, .gp scripts, .svg) and report.html into the run folder.
/// A missing gnuplot is noted in the report, not an error.
void write_report(const ReportInputs& in);

}  // namespace poise::studies
