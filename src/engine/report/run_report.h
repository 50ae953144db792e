#pragma once
/// report.html of a run of any kind: the answer first, then what was run, the study's own
/// sections (ProcedureStudy::report_sections), the outputs, sweeps, contributions,
/// convergence, figures, notes and provenance, all from summary.json and the run's results.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/kind_interface/procedure_study.h"
#include "engine/results/requirements.h"
#include "engine/results/sensitivity_output.h"
#include "engine/run/run_plan.h"

namespace poise::engine {

/// Everything a finished run's summary and report are made from.
struct FinishedRun {
  const StudyConfig& cfg;
  const ProcedureStudy& study;
  const RunPlan& plan;
  const McResult& mc;
  std::size_t ran = 0, resumed = 0, rhs_uncounted = 0;
  std::string status;
  const std::vector<std::string>& sources;  ///< of the within-sample randomness
  const ToleranceGroups& tolerances;
  const std::vector<Requirement>& requirements;
};

/// The page, with its figures written into `plots_dir` (gnuplot; `plots` false: none).
std::string run_report_html(const nlohmann::json& summary, const FinishedRun& run,
                            const std::filesystem::path& plots_dir, bool plots);

}  // namespace poise::engine
