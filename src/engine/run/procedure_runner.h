#pragma once
/// Writes the result folder of a procedure study (procedure_study.h): samples.csv streamed
/// in sample order (with run.json, so that `--resume` can continue it), samples.h5,
/// summary.json, plots/ and report.html.
#include <functional>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/kind_interface/procedure_study.h"
#include "engine/results/requirements.h"
#include "engine/run/procedure_sweeps.h"
#include "engine/run/study_runner.h"
#include "engine/study_files/study_config.h"

namespace poise::engine {

/// Runs the study and writes its folder: samples.csv (streamed), samples.h5 (the same columns
/// with their declared units), summary.json (statistics, references, requirements and their
/// answer, sweeps, sensitivity, provenance), plots/ and report.html (the answer first).
/// `make_study` builds the study for a config (the study file's, with the run's design
/// settings: the sensitivity layout is set here; a sweep's value as an override), a sample
/// count and a seed (those of a resumed run may differ from the study file's).
std::string run_procedure_study(const StudyConfig& cfg, const StudyFactory& make_study, const RunOptions& options,
                                const std::vector<Requirement>& requirements);

/// One sample alone, as JSON (inputs and outputs by name).
nlohmann::json replay_procedure_sample(const ProcedureStudy& study, std::size_t index);

}  // namespace poise::engine
