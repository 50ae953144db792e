#pragma once
#include <vector>
#include <map>
#include <memory>
/// The los_obstruction study: the optical beam of a two-axis seeker traced through its own
/// frames and housing over the field of regard (geometry/obstruction.h), and the clearance
/// between the moving frames and the housing, for the nominal design and for every sample
/// of the shafting tolerances of the LOS study (the same SeekerSampler and exact chain, so
/// the frames turn with each sample's axis tilts, run-out and collimation).
///
/// Model: a seeker model with a [geometry] section (studies/seeker_geometry.h).
/// Per-sample outputs (over the study's yaw x pitch grid):
///   min_fraction_pct, mean_fraction_pct  unobstructed share of the beam, least and mean
///   full_field_pct                       share of grid points where the whole beam passes
///   min_fraction_shift_ppm               least fraction minus the nominal design's
///   min_clearance_mm                     least of the three clearances below
///   ring_housing_mm, barrel_housing_mm, barrel_ring_mm
///   clearance_shift_um                   min_clearance minus the nominal design's
#include <nlohmann/json.hpp>
#include <string>

#include "engine/input_evaluation.h"
#include "engine/study_config.h"
#include "engine/study_runner.h"

namespace poise::studies {

struct OutputSpec;
/// The per-sample outputs with units.
std::vector<OutputSpec> obstruction_outputs();
/// The study's outputs at given inputs (the seeker's columns; engine/input_evaluation.h).
std::unique_ptr<InputEvaluator> obstruction_input_evaluator(const StudyConfig& cfg,
                                                             const std::map<std::string, std::string>& model_overrides);

std::string validate_obstruction_study(const StudyConfig& cfg);
std::string run_obstruction_study(const StudyConfig& cfg, const RunOptions& options);
nlohmann::json replay_obstruction_sample(const StudyConfig& cfg, std::size_t index, const RunOptions& options);

}  // namespace poise::studies
