#pragma once
/// The Monte Carlo set beside a budget (`poise budget`, [budget] model/output/samples/seed):
/// the model file's exact chain sampled, one output's values returned. Every study kind that
/// names a model_kind() (engine/kind_interface/study_kind.h) serves the model files of that [model] kind,
/// through the kind interface (model_study, outputs, evaluate); no list to edit:
///   outputs(model)            the per-sample outputs it can give, with their units
///   tolerance_keys(model)     the model's sampled tolerances, dotted ("yaw.perpendicularity"),
///                             for a budget line's model_key
///   run(model, output, samples, seed) -> the output's values (same seed, same values)
/// It lives in the budget layer (it was the command line's): Python's poise.budget and the
/// command reach the same call.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace poise::budget {

struct MonteCarloOutput {
  std::string name, unit, description;
};

struct MonteCarloValues {
  std::vector<double> values;  ///< the output of every sample that did not fail, in the output's unit
  std::size_t samples = 0, failures = 0;
  double wall_seconds = 0.0;
};

struct MonteCarloKind {
  std::string model_kind;  ///< [model] kind of the model files it samples
  std::string description;
  std::function<std::vector<MonteCarloOutput>(const std::string& model_path)> outputs;
  std::function<std::vector<std::string>(const std::string& model_path)> tolerance_keys;
  std::function<MonteCarloValues(const std::string& model_path, const std::string& output, std::size_t samples,
                                 std::uint64_t seed)>
      run;
};

/// The study kinds that sample a model file alone.
std::vector<MonteCarloKind> monte_carlo_kinds();
/// The one for a model kind, or nullopt.
std::optional<MonteCarloKind> find_monte_carlo_kind(const std::string& model_kind);
/// [model] kind of a model file ("" when it has none). Throws engine::ValidationError when the
/// file does not parse.
std::string model_kind_of(const std::string& model_path);

}  // namespace poise::budget
