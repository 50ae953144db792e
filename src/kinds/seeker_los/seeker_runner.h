#pragma once
/// Runs a seeker_los study (the LOS error of a two-axis seeker from its shafting
/// tolerances) and writes its result folder:
///   samples.csv   one row per sample: index, status, drawn inputs, outputs, message
///                 (streamed chunk by chunk, in sample order)
///   samples.h5    the total LOS error of every sample at every grid point (HDF5,
///                 engine/wide_columns.h), from which the pooled figures and maps are read back
///   summary.json  statistics of every output with 95% CIs, the pooled field figures,
///                 contributions, sweeps, declared references, requirements and the answer,
///                 provenance
///   plots/        gnuplot scripts, data and SVG figures (inline in report.html)
///   report.html   the report a reviewer reads
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/study_config.h"
#include "engine/study_runner.h"

namespace poise::studies {

std::string validate_seeker_study(const StudyConfig& cfg);
/// `requirements`: the study's, judged on the run (summary.json "requirements" and "answer").
std::string run_seeker_study(const StudyConfig& cfg, const RunOptions& options, const std::vector<Requirement>& requirements);
/// Sample `index` alone: inputs, outputs and the pointing error at every grid point.
nlohmann::json replay_seeker_sample(const StudyConfig& cfg, std::size_t index, const RunOptions& options);

}  // namespace poise::studies
