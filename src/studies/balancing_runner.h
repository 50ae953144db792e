#pragma once
/// Runs a balancing-machine study file (kind = "balancing_machine", balancing_study.h) and
/// writes its result folder like the other procedure studies (procedure_runner.h), with the
/// machine's table, the separation, U_mar and stability figures and the error histograms.
#include <string>

#include <nlohmann/json.hpp>

#include "studies/study_config.h"
#include "studies/study_runner.h"

namespace poise::studies {

std::string run_balancing_study(const StudyConfig& cfg, const RunOptions& options);
std::string validate_balancing_study(const StudyConfig& cfg);
nlohmann::json replay_balancing_sample(const StudyConfig& cfg, std::size_t index, const RunOptions& options);

}  // namespace poise::studies
