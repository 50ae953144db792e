#pragma once
/// Independent whole runs of a study (the values of its sweeps, the runs of its contribution
/// table) spread over the MPI ranks (sampling/distributed.h): rank p makes runs p - 1,
/// p - 1 + ranks, ... (rank 0 the last of each round: it has the run's folder to write) on its
/// own threads, and each run's result (JSON) is gathered at rank 0 in run order. A run depends only on its own inputs
/// and the run's seed, so the results equal a one-process run's, whatever the rank count. One process: the runs, in
/// order, and nothing else (a run's exception leaves as it is). Several: every rank must call it with the same count; a
/// run that throws on any rank is reported by rank 0 as poise::Error with its message and the rank it ran on.
#include <cstddef>
#include <functional>
#include <vector>

#include <nlohmann/json.hpp>

namespace poise::engine {

/// Results of runs 0..count-1 on rank 0 (in run order); an empty vector on the other ranks.
std::vector<nlohmann::json> runs_over_ranks(std::size_t count, const std::function<nlohmann::json(std::size_t)>& run);

}  // namespace poise::engine
