#pragma once
/// The los_obstruction study: the optical beam of a two-axis seeker traced through its own
/// frames and housing over the field of regard (geometry/obstruction.h), and the clearance
/// between the moving frames and the housing, for the nominal design and for every sample
/// of the shafting tolerances of the LOS study (the same SeekerSampler and exact chain, so
/// the frames turn with each sample's axis tilts, run-out and collimation). The engine runs
/// it as every kind (engine/run/procedure_runner.h); summary.json "details" holds the nominal
/// design's maps, the report its figures.
///
/// Model: a seeker model with a [geometry] section (model_files/seeker_geometry.h).
/// Per-sample outputs (over the study's yaw x pitch grid):
///   min_fraction_pct, mean_fraction_pct  unobstructed share of the beam, least and mean
///   full_field_pct                       share of grid points where the whole beam passes
///   min_fraction_shift_ppm               least fraction minus the nominal design's
///   min_clearance_mm                     least of the three clearances below
///   ring_housing_mm, barrel_housing_mm, barrel_ring_mm
///   clearance_shift_um                   min_clearance minus the nominal design's
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "engine/kind_interface/procedure_study.h"
#include "engine/study_files/study_config.h"

namespace poise::kinds::los_obstruction {
using engine::ProcedureStudy;
using engine::StudyConfig;

/// The study of `cfg` on its model with `model_overrides`, `samples` samples from `seed`.
std::unique_ptr<ProcedureStudy> make_obstruction_study(const StudyConfig& cfg,
                                                       const std::map<std::string, std::string>& model_overrides,
                                                       std::size_t samples, std::uint64_t seed);
/// Validates the study with its model; a short human summary.
std::string validate_obstruction_study(const StudyConfig& cfg);

}  // namespace poise::kinds::los_obstruction
