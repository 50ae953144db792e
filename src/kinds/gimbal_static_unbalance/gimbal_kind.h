#pragma once
/// The gimbal_static_unbalance study kind: the static-unbalance test of a gimbal axis
/// (Yang 2015) simulated end to end per sample (procedures/static_unbalance_procedure.h:
/// the disk rotor's Lagrange equations integrated with CVODE at each turntable position,
/// servo-driven oscillation, current integration, sine fit, counterweight) over the rig's
/// tolerances. Runs through the engine's procedure runner (engine/kind_interface/procedure_kind.h).
#include <memory>

#include "engine/kind_interface/study_kind.h"

namespace poise::kinds::gimbal_static_unbalance {
using engine::StudyKind;

std::unique_ptr<StudyKind> make_gimbal_static_unbalance_kind();

}  // namespace poise::kinds::gimbal_static_unbalance
