#pragma once
/// summary.json of a seeker_los run (seeker_runner.cc makes the run): the study, its LOS limit,
/// sampling and inputs, every output's statistics, the pooled field figures, references,
/// failures, convergence, Sobol indices, sweeps and contributions, requirements and the answer,
/// provenance.
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/convergence.h"
#include "engine/output_spec.h"
#include "engine/requirements.h"
#include "engine/run_plan.h"
#include "engine/sensitivity_output.h"
#include "engine/study_config.h"
#include "engine/study_runner.h"
#include "kinds/seeker_los/seeker_los_study.h"
#include "model_files/seeker_model.h"

namespace poise::studies {

/// A statistic summary with its unit and (optional) description.
nlohmann::json output_summary_json(const sampling::Summary& s, const std::string& unit, const std::string& description);

/// The seeker's outputs as declared.
std::vector<OutputSpec> seeker_output_specs();
/// The values of one seeker output of a run, for a requirement's verdict.
OutputValues seeker_values(const SeekerMcResult& mc, const std::string& name, std::size_t replicate_size,
                           bool independent);

/// summary.json's "sweeps" and "contributions".
struct SideResults {
  nlohmann::json sweeps = nlohmann::json::array(), contributions = nlohmann::json::array();
};

/// Everything summary.json is made from.
struct SeekerRun {
  const StudyConfig& cfg;
  const SeekerModel& model;
  const SeekerLosStudy& study;
  const SeekerMcResult& mc;
  const RunPlan& plan;
  const StopRule& rule;
  const ToleranceGroups& tolerances;
  const std::vector<Requirement>& requirements;
  std::string status;
  std::size_t ran = 0;
};

/// summary.json of a finished run (rank 0).
nlohmann::json seeker_summary(const SeekerRun& r, const SideResults& side, const RunOptions& options);

}  // namespace poise::studies
