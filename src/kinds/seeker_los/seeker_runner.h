#pragma once
/// Validation and replay of a seeker_los study (the LOS error of a two-axis seeker from its
/// shafting tolerances). Its run is the engine's one path (engine/run/procedure_runner.h): the
/// study (seeker_los_study.h) streams each sample's grid values into samples.h5 and adds its
/// field figures to summary.json "details" and its own report sections.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/run/study_runner.h"
#include "engine/study_files/study_config.h"

namespace poise::kinds::seeker_los {
using engine::RunOptions;
using engine::StudyConfig;

std::string validate_seeker_study(const StudyConfig& cfg);
/// Sample `index` alone: inputs, outputs and the pointing error at every grid point.
nlohmann::json replay_seeker_sample(const StudyConfig& cfg, std::size_t index, const RunOptions& options);

}  // namespace poise::kinds::seeker_los
