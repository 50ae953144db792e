#pragma once
/// Runs a platform balancing study (kind "platform_balancing", platform_study.h) and writes
/// its result folder through the procedure runner (samples.csv, run.json for --resume,
/// summary.json, plots/, report.html with the per-axis residual torques, the comparison of
/// test orders and the combined LOS budget).
#include <string>

#include <nlohmann/json.hpp>

#include "studies/study_config.h"
#include "studies/study_runner.h"

namespace poise::studies {

std::string run_platform_study(const StudyConfig& cfg, const RunOptions& options);
std::string validate_platform_study(const StudyConfig& cfg);
nlohmann::json replay_platform_sample(const StudyConfig& cfg, std::size_t index, const RunOptions& options);

/// The shafting LOS error of the seeker study named in [platform.shafting]: the greatest
/// error over the field of regard of each unit (arcsec), and the pixel IFOV (arcsec).
struct ShaftingLos {
  std::vector<double> los_max_arcsec;
  double pixel_arcsec = 0.0;
};
ShaftingLos compute_shafting_los(const StudyConfig& cfg, int threads);

}  // namespace poise::studies
