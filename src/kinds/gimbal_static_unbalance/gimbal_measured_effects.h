#pragma once
/// The effects a residual diagnosis finds in a measured static-unbalance table, as keys of the
/// gimbal simulation model (StudyKind::effects_in_model; `poise diagnose --study`). Table unit
/// -> SI:
///   harmonic 2        disturbances.harmonic2_torque = amplitude, harmonic2_phase = phase
///                     (both the simulator's T2 sin(2 theta + psi2) and the diagnosis'
///                     amplitude sin(2 theta + phase))
///   time_drift        disturbances.offset_drift_rate = slope / K_T (the model's nominal K_T;
///                     needs the table's time stamps: a drift per measurement has no rate)
///   direction_offset  disturbances.direction_torque = half_difference (torque +-T_d by sweep)
///   outlier           disturbances.bump_position = row, bump_torque = offset
/// Other effects have no key in the model and are listed as such. The outputs compared: the
/// test's errors (torque error first) and its sine fit's residual.
#include <vector>

#include "engine/kind_interface/measured_effects.h"
#include "engine/kind_interface/output_spec.h"
#include "engine/study_files/study_config.h"
#include "estimators/residual_diagnosis.h"
#include "estimators/torque_table.h"

namespace poise::kinds::gimbal_static_unbalance {

engine::EffectsInModel gimbal_effects_in_model(const engine::StudyConfig& cfg,
                                               const std::vector<engine::OutputSpec>& outputs,
                                               const estimators::TorqueTable& table,
                                               const estimators::DiagnosisResult& result);

}  // namespace poise::kinds::gimbal_static_unbalance
