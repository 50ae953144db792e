#pragma once
/// The LOS study's outputs at input values a caller gives (engine/kind_interface/input_evaluation.h): each
/// point's inputs (samples.csv's columns and units: k_load, the perpendicularity tilts, the
/// run-out amplitudes and phases, ...) are the error realization itself, so the exact chain
/// is evaluated over the field of regard as for a drawn sample. No randomness of its own.
#include <memory>

#include "engine/kind_interface/input_evaluation.h"
#include "engine/study_files/study_config.h"
#include "model_files/seeker_model.h"

namespace poise::kinds::seeker_los {
using engine::InputEvaluator;
using engine::StudyConfig;
using model_files::SeekerModel;

std::unique_ptr<InputEvaluator> make_seeker_input_evaluator(const StudyConfig& cfg, SeekerModel model);

}  // namespace poise::kinds::seeker_los
