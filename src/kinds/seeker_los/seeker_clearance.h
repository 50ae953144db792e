#pragma once
/// The nominal clearance of a seeker's moving frames to its housing, as an output of the LOS
/// study for a bearing-span sizing (a study's optional [clearance] output = true, see
/// seeker_los_sections.h): the frames are built from the model's [geometry] and its current
/// bearing spans, so each design point of the optimizer gets its own frames.
#include <cstddef>

#include "model_files/seeker_model.h"

namespace poise::kinds::seeker_los {
using model_files::SeekerModel;

/// Least clearance (m; negative = interference) of the yaw ring and the barrel to the housing
/// and of the barrel to the ring, nominal poses on a yaw_points x pitch_points grid over the
/// model's field of regard. Throws poise::Error if the model has no [geometry].
double nominal_min_clearance(const SeekerModel& model, std::size_t yaw_points, std::size_t pitch_points);

}  // namespace poise::kinds::seeker_los
