#pragma once
/// How a kind's model takes the effects a residual diagnosis found in a measured test table
/// (estimators/residual_diagnosis.h), for `poise diagnose --study` (cli/diagnose_loop.h): each
/// effect mapped to the model keys it stands for, with its value in the model's terms, and the
/// study's outputs that a measured residual is set beside. A kind declares it
/// (StudyKind::effects_in_model); the loop names no kind.
#include <map>
#include <string>
#include <vector>

namespace poise::engine {

struct EffectsInModel {
  std::map<std::string, std::string> overrides;  ///< model key -> value with its unit
  std::vector<std::string> unmapped;             ///< effects no model key stands for (with why, where not plain)
  /// The study's outputs to set beside the measured residual (the study's order).
  std::vector<std::string> error_outputs;
  std::string headline_output;      ///< the one the answer quotes ("" = the first)
  std::string fit_residual_output;  ///< the simulated test's fit residual ("" = none)
};

}  // namespace poise::engine
