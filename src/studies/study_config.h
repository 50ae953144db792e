#pragma once
/// A study file (studies/*.toml): what to run, on which model, how to sample, what to
/// report. Strict like the model files: unknown keys, missing units and non-physical
/// values are refused with file, line, key, value and what was expected.
///
///   [study]     name, kind = "seeker_los", model (path relative to the study file),
///               title, notes
///   [sampling]  method = "sobol" | "lhs" | "monte_carlo", samples, seed
///   [grid]      yaw_points, pitch_points (over the model's field of regard)
///   [requirement] los_error = "1 px" (or any angle)
///   [overrides] "dotted.model.key" = "value"      (optional)
///   [[sweep]]   parameter = "dotted.model.key", values = [...], samples (optional)
///   [output]    plots = true, block = 1024, contribution_samples = 4096  (optional)
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "sampling/design.h"

namespace poise::studies {

struct SweepSpec {
  std::string parameter;
  std::vector<std::string> values;
  std::size_t samples = 0;
};

struct StudyConfig {
  std::string file;        ///< path of the study file
  std::string name, kind, title, notes;
  std::string model_path;  ///< resolved against the study file's folder
  sampling::SamplingMethod method = sampling::SamplingMethod::kSobol;
  std::size_t samples = 0;
  std::uint64_t seed = 0;
  std::size_t yaw_points = 13, pitch_points = 13;
  double requirement = 0.0;       ///< as written, in its unit's SI (rad or px)
  bool requirement_in_pixels = true;
  std::string requirement_text;
  std::map<std::string, std::string> overrides;
  std::vector<SweepSpec> sweeps;
  bool plots = true;
  std::size_t block = 1024;
  /// Contribution of each tolerance: the study re-run with that tolerance set to zero
  /// (same random numbers), with this many samples; 0 switches it off.
  std::size_t contribution_samples = 4096;
};

/// Loads and validates a study file (not its model). Throws ValidationError.
StudyConfig load_study(const std::string& path);

}  // namespace poise::studies
