#pragma once
/// An optimization study (`poise optimize FILE.toml`): design variables (model keys with
/// bounds), an objective (a statistic of an output of a base Monte Carlo study, or the sum
/// of design variables such as spans), constraints (statistics with at_least / at_most),
/// optional discrete choices enumerated around the continuous search, and the NLopt
/// algorithm. Every evaluation runs the base study with the same seed and sample count
/// (common random numbers), so the objective is a smooth function of the design; the optimum
/// is then verified with fresh random numbers and more samples, with confidence intervals.
///
///   [optimization]  name, study (base study file, relative to this file), title, notes,
///                   samples, seed, algorithm, max_evaluations, xtol_rel
///   [[variable]]    parameter (dotted model key), lower, upper, start ("<number> <unit>")
///   [[choice]]      parameter, values = ["...", ...]      (discrete, enumerated)
///   [objective]     output + statistic, or variable_sum = ["key", ...] (minimized)
///   [[constraint]]  output, statistic, at_least = x | at_most = x  (in the output's unit)
///   [verification]  samples, seed
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "optimize/optimizer.h"
#include "studies/study_config.h"
#include "studies/study_runner.h"

namespace poise::optimize {

struct DesignVariable {
  std::string parameter;  ///< dotted model key
  std::string unit;       ///< unit the bounds were written in ("mm"); "" if dimensionless
  double lower = 0.0, upper = 0.0, start = 0.0;  ///< in that unit
};

struct Choice {
  std::string parameter;
  std::vector<std::string> values;
};

struct Requirement {
  std::string output, statistic;
  std::optional<double> at_least, at_most;
};

struct OptimizationSpec {
  std::string file, name, title, notes;
  studies::StudyConfig base;  ///< the base study
  std::size_t samples = 64;
  std::uint64_t seed = 1;
  Algorithm algorithm = Algorithm::kCobyla;
  int max_evaluations = 100;
  double xtol_rel = 1e-3;
  std::vector<DesignVariable> variables;
  std::vector<Choice> choices;
  std::string objective_output, objective_statistic;  ///< empty output: variable_sum
  std::vector<std::string> variable_sum;
  std::vector<Requirement> constraints;
  std::size_t verification_samples = 256;
  std::uint64_t verification_seed = 2;
};

/// Loads and validates the file, its base study and that the outputs exist. Throws
/// studies::ValidationError (file, line, key, value, expected).
OptimizationSpec load_optimization(const std::string& path);

struct ChoiceResult {
  std::map<std::string, std::string> choice;  ///< parameter -> value
  Result result;                              ///< in the variables' units
};

struct OptimizationOutcome {
  std::vector<ChoiceResult> runs;  ///< one per combination of the choices (or one)
  std::size_t best = 0;            ///< index into runs of the best feasible, if any
  bool feasible = false;
  std::string message;             ///< why not, when infeasible
  std::map<std::string, std::string> optimum;  ///< overrides of the optimum
  nlohmann::json verification;     ///< the verification run (statistics with CIs)
};

/// Runs the optimization (and the verification of the optimum). Does not write anything.
OptimizationOutcome optimize(const OptimizationSpec& spec, int threads, bool progress);

/// Runs it and writes results/<name>/<run id>/ (history.csv, summary.json, plots, report.html).
/// Returns the folder. Throws poise::Error after writing the folder if no design is feasible.
std::string run_optimization(const std::string& path, const studies::RunOptions& options);

}  // namespace poise::optimize
