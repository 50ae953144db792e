#pragma once
/// Independent whole runs of a study (the values of its sweeps, the runs of its contribution
/// table) spread over the MPI ranks (sampling/distributed.h): each rank takes the next run no
/// rank has taken yet (sampling::SharedCounter) and makes it on its own threads, so a rank that
/// starts late (rank 0, which finishes the run's statistics first) makes fewer; each run's
/// result (JSON) is gathered at rank 0 in run order. A run depends only on its own inputs and
/// the run's seed, so the results equal a one-process run's, whatever the rank count and
/// whichever rank made it. One process: the runs, in order, and nothing else (a run's exception
/// leaves as it is). Several: every rank must call it with the same count; a run that throws is
/// reported by rank 0 as poise::Error with its message and the rank it ran on (the first such
/// run's, in run order).
#include <cstddef>
#include <functional>
#include <vector>

#include <nlohmann/json.hpp>

namespace poise::engine {

/// Results of runs 0..count-1 on rank 0 (in run order); an empty vector on the other ranks.
std::vector<nlohmann::json> runs_over_ranks(std::size_t count, const std::function<nlohmann::json(std::size_t)>& run);

}  // namespace poise::engine
