#pragma once
/// Runs a gimbal static-unbalance study file and writes its result folder (samples.csv,
/// summary.json, plots/, report.html), like the LOS study (study_runner.h).
#include <string>

#include "studies/study_config.h"
#include "studies/study_runner.h"

namespace poise::studies {

std::string run_gimbal_study(const StudyConfig& cfg, const RunOptions& options);
std::string validate_gimbal_study(const StudyConfig& cfg);
nlohmann::json replay_gimbal_sample(const StudyConfig& cfg, std::size_t index, const RunOptions& options);

}  // namespace poise::studies
