#pragma once
/// Plots (gnuplot, headless SVG) and report.html of a LOS study run.
#include <nlohmann/json.hpp>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "models/seeker_los_budget.h"
#include "studies/seeker_los_study.h"

namespace poise::studies {

struct ReportInputs {
  std::string dir;                 ///< run folder
  const nlohmann::json& summary;   ///< what summary.json holds
  const models::WangBudget& budget;
  const SeekerMcResult& mc;
  const std::vector<double>& alpha;  ///< grid, rad
  const std::vector<double>& beta;
  bool plots = true;
};

/// Writes plots/ (data, .gp scripts, .svg) and report.html into the run folder.
/// A missing gnuplot is noted in the report, not an error.
void write_report(const ReportInputs& in);

/// Runs gnuplot on a script; returns false (and the reason) if it failed or is absent.
bool run_gnuplot(const std::string& script_path, std::string* why);

/// Writes dir/name.gp (SVG terminal, 720x420, grid, then `script`) and runs gnuplot: on
/// success appends "name.svg" to `figures`; on failure writes why into `html` (a small note
/// where the figure would be). Returns whether the figure was made.
bool svg_plot(const std::filesystem::path& dir, const std::string& name, const std::string& script,
              std::vector<std::string>& figures, std::ostringstream& html);

}  // namespace poise::studies
