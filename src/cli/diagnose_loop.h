#pragma once
/// Closes the loop at the table level for `poise diagnose --study`: each effect the diagnosis
/// found is mapped to the [disturbances] key of the gimbal simulation model it stands for,
/// the study is evaluated (in memory, engine::evaluate_study) without and with those
/// overrides on the same random numbers, and the simulated errors are set beside the
/// measured residual: "with this effect in the model the simulated test's error is X; the
/// measured one is Y".
///
/// Mapping (table unit -> SI):
///   harmonic 2        disturbances.harmonic2_torque = amplitude, harmonic2_phase = phase
///                     (both the simulator's T2 sin(2 theta + psi2) and the diagnosis'
///                     amplitude sin(2 theta + phase))
///   time_drift        disturbances.offset_drift_rate = slope / K_T (the model's nominal K_T;
///                     needs time_s in the table: a drift per measurement has no rate)
///   direction_offset  disturbances.direction_torque = half_difference (torque +-T_d by sweep)
///   outlier           disturbances.bump_position = row, bump_torque = offset
/// Other effects have no key in the simulation model and are listed as such.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "estimators/residual_diagnosis.h"
#include "estimators/torque_table.h"

namespace poise::cli {

/// One output of the study with and without the effects (over the same samples).
struct LoopOutput {
  std::string name;
  double mean_without = 0.0, sd_without = 0.0, mean_with = 0.0, sd_with = 0.0;
};

struct LoopResult {
  std::string study;
  std::vector<std::pair<std::string, std::string>> overrides;  ///< key, value
  std::vector<std::string> unmapped;                           ///< effects with no key
  std::vector<LoopOutput> outputs;                             ///< the study's error outputs
  std::size_t samples = 0;
  double measured_rmse = 0.0;  ///< table unit
  std::string unit;
  std::string sentence;  ///< "with these effects in the model ..."
};

/// Maps, evaluates and compares (see above). Throws poise::Error / ValidationError for a
/// study that is not a gimbal_static_unbalance one or whose model refuses an override.
LoopResult close_the_loop(const std::string& study_path, const estimators::TorqueTable& table,
                          const estimators::DiagnosisResult& result, std::size_t samples);

nlohmann::json loop_json(const LoopResult& r);
std::string loop_text(const LoopResult& r);

}  // namespace poise::cli
