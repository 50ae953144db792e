#pragma once
/// One in-memory run of any study whose kind evaluates in memory (StudyKind::evaluate)
/// with extra model overrides: the per-sample outputs, nothing written. The optimizer's
/// objective and constraints are statistics of these outputs; with the same seed and sample
/// count every design point sees the same random numbers (common random numbers), so a
/// statistic is a smooth function of the design.
#include <map>
#include <string>
#include <vector>

#include "engine/results/mc_result.h"
#include "engine/study_files/study_config.h"

namespace poise::engine {

/// Runs `cfg` (its model with cfg.overrides, then `overrides` on top) with `samples` samples
/// and `seed`. Study keys among the overrides (group.positions, ...: apply_study_overrides)
/// change the study's test plan instead of its model. Throws ValidationError if an override is not valid for the model.
McResult evaluate_study(const StudyConfig& cfg, const std::map<std::string, std::string>& overrides,
                        std::size_t samples, std::uint64_t seed, int threads);

/// Output names of a study without running it (validates study and model).
std::vector<std::string> study_output_names(const StudyConfig& cfg);

/// A statistic of values: "mean", "std", "min", "max", "p<q>" (p50, p95, p99.73, ...), or
/// "fraction_le:<x>" / "fraction_ge:<x>" (share of samples at most / at least x),
/// "fraction_within:<lo>:<hi>" (share within [lo, hi]; a NaN value is not within).
/// Throws poise::Error for an unknown statistic or no values.
double statistic(std::vector<double> values, const std::string& name);
/// Whether `name` is a statistic statistic() understands (for validation).
bool is_statistic(const std::string& name);

}  // namespace poise::engine
