#pragma once
/// Closes the loop at the table level for `poise diagnose --study`: the study's kind maps each
/// effect the diagnosis found to the model keys it stands for (StudyKind::effects_in_model,
/// engine/kind_interface/measured_effects.h; the gimbal's mapping is in
/// kinds/gimbal_static_unbalance/gimbal_measured_effects.h), the study is evaluated (in memory,
/// engine::evaluate_study) without and with those overrides on the same random numbers, and
/// the outputs the kind names are set beside the measured residual: "with this effect in the
/// model the simulated test's error is X; the measured one is Y". It names no kind.
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
/// study whose kind's model takes no measured effect or refuses an override.
LoopResult close_the_loop(const std::string& study_path, const estimators::TorqueTable& table,
                          const estimators::DiagnosisResult& result, std::size_t samples);

nlohmann::json loop_json(const LoopResult& r);
std::string loop_text(const LoopResult& r);

}  // namespace poise::cli
