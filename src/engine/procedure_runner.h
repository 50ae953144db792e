#pragma once
/// Writes the result folder of a procedure study (procedure_study.h): samples.csv streamed
/// in sample order (with run.json, so that `--resume` can continue it), summary.json with
/// statistics, the paper comparison and provenance, plots/ and report.html.
#include <functional>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/procedure_study.h"
#include "engine/study_config.h"
#include "engine/study_runner.h"

namespace poise::studies {

/// Builds the study for a sample count and seed (those of a resumed run may differ from
/// the study file's).
/// Builds the study for a config (the study file's, with the run's design settings: the
/// sensitivity layout is set here), a sample count and a seed (those of a resumed run may
/// differ from the study file's).
using StudyFactory = std::function<std::unique_ptr<ProcedureStudy>(const StudyConfig& cfg, std::size_t samples, std::uint64_t seed)>;

std::string run_procedure_study(const StudyConfig& cfg, const StudyFactory& make_study, const RunOptions& options);

/// One sample alone, as JSON (inputs and outputs by name).
nlohmann::json replay_procedure_sample(const ProcedureStudy& study, std::size_t index);

}  // namespace poise::studies
