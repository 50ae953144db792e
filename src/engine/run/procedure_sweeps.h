#pragma once
/// [[sweep]] for every study run through procedure_runner: the study re-run at each value of
/// one model key with the run's seed (common random numbers: the same draws at every value,
/// so differences between values are the design's), each value's outputs summarized with
/// 95% intervals and the study's requirements judged on it. summary.json "sweeps":
///   [{"parameter", "samples", "points": [{"value", "value_si", "samples", "failures",
///                                         "outputs": {name: statistics}, "requirements"}]}]
/// and the report's "Sweeps" section: a figure per sweep and shown output (the statistic a
/// requirement names, else p95, against the value in the unit it was written in) and a table.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/kind_interface/output_spec.h"
#include "engine/kind_interface/procedure_study.h"
#include "engine/results/requirements.h"
#include "engine/study_files/study_config.h"

namespace poise::engine {

using StudyFactory =
    std::function<std::unique_ptr<ProcedureStudy>(const StudyConfig& cfg, std::size_t samples, std::uint64_t seed)>;

/// Runs every sweep of `cfg` and returns summary.json's "sweeps" (on rank 0; null on the
/// others). Every rank of an MPI run calls it: the (sweep, value) runs are spread over the
/// ranks (runs_over_ranks.h). `run_samples`: the run's sample count (a sweep without its own
/// samples takes it).
nlohmann::json run_procedure_sweeps(const StudyConfig& cfg, const StudyFactory& make_study, std::size_t run_samples,
                                    std::uint64_t seed, int threads, bool progress,
                                    const std::vector<Requirement>& requirements,
                                    const std::vector<OutputSpec>& outputs);

/// The number and unit of a value as written ("70 mm" -> 70, "mm"; NaN when it is not a
/// number): sweep axes in the user's own unit, not SI.
std::pair<double, std::string> as_written(const std::string& text);

}  // namespace poise::engine
