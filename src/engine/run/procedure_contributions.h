#pragma once
/// Contributions for every study run through procedure_runner ([output] contribution_samples
/// > 0; off by default, each is a whole extra run): the study re-run with each model tolerance
/// set to zero in turn, with the run's seed (common random numbers), so the drop of a
/// statistic is that tolerance's share of it. A tolerance is zeroed by overriding its
/// `tolerance` value with 0 in the unit the model file writes it in; one given as a range
/// (min, max) has no zero and is listed as not zeroed. summary.json "contributions":
///   [{"without": "(nothing: all tolerances)" | key, "samples", "failures",
///     "outputs": {name: statistics}}] (a key whose run could not be made has "skipped": why)
/// and the report's "Which tolerance drives the error" section: for each shown statistic (those
/// the requirements name, else p95 of the first output) a table of the drops and a tornado.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/kind_interface/output_spec.h"
#include "engine/run/procedure_sweeps.h"

namespace poise::engine {

/// Runs the contributions of the model tolerances `tolerance_keys` ("tolerances.kt_drift") and
/// returns summary.json's "contributions" (on rank 0; null on the others). Every rank of an
/// MPI run calls it: the runs are spread over the ranks (runs_over_ranks.h).
nlohmann::json run_procedure_contributions(const StudyConfig& cfg, const StudyFactory& make_study,
                                           const std::vector<std::string>& tolerance_keys, std::size_t samples,
                                           std::uint64_t seed, int threads, bool progress,
                                           const std::vector<OutputSpec>& outputs);

}  // namespace poise::engine
