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
///   [pareto]        output, statistic, points: a second objective (minimized); the front
///                   of the two is traced by the epsilon-constraint method (below)
///   [overrides]     "key" = "value": model or study keys set for every evaluation
///   [verification]  samples, seed
///
/// Two objectives ([pareto]): for each combination of the choices, minimize the objective,
/// then the second objective, then `points` times the objective with the second one
/// bounded by levels evenly between the two minima (epsilon-constraint). Every evaluation of
/// every search is kept; the Pareto front is the feasible evaluations that no other one
/// beats on both objectives. Each front point is verified with fresh random numbers.
///
/// Choices compared: with more than one combination, the best design of each combination is
/// verified with the same fresh random numbers, and its objective is compared with the best
/// combination's: paired bootstrap 95% interval of the difference and the bootstrap share
/// of resamples in which the best stays ahead.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "optimize/optimizer.h"
#include "engine/study_config.h"
#include "engine/study_runner.h"

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

struct ParetoSpec {
  std::string output, statistic;  ///< the second objective (minimized)
  int points = 3;                 ///< epsilon levels between the two single-objective optima
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
  std::optional<ParetoSpec> pareto;
  std::map<std::string, std::string> overrides;  ///< [overrides], under variables and choices
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

/// One evaluation of any search (for the Pareto front).
struct ParetoPoint {
  std::size_t choice = 0;      ///< index of the combination of choices
  std::string search;          ///< "objective", "second", "epsilon <level>"
  std::vector<double> x;       ///< variables in their units
  double objective = NAN, second = NAN;
  bool feasible = false;       ///< ok and every constraint met (the epsilon bound aside)
};

struct OptimizationOutcome {
  std::vector<ChoiceResult> runs;  ///< one per combination of the choices (or one)
  std::size_t best = 0;            ///< index into runs of the best feasible, if any
  bool feasible = false;
  std::string message;             ///< why not, when infeasible
  std::map<std::string, std::string> optimum;  ///< overrides of the optimum
  nlohmann::json verification;     ///< the verification run (statistics with CIs)
  std::vector<std::map<std::string, std::string>> choices;  ///< the combinations, in order
  std::vector<ParetoPoint> pool;   ///< every evaluation ([pareto] only)
  std::vector<std::size_t> front;  ///< indices into pool, by increasing second objective
  nlohmann::json front_verification;  ///< per front point: both objectives with 95% CIs
  nlohmann::json comparison;       ///< choices compared on fresh random numbers
};

/// A statistic of `values` with a bootstrap 95% percentile interval (`resamples` resamples,
/// deterministic in `seed`): {value, lo, hi}.
nlohmann::json statistic_with_ci(const std::vector<double>& values, const std::string& statistic,
                                 std::uint64_t seed, int resamples = 1000);

/// Runs the optimization (and the verification of the optimum). Does not write anything.
OptimizationOutcome optimize(const OptimizationSpec& spec, int threads, bool progress);

/// Runs it and writes results/<name>/<run id>/ (history.csv, summary.json, plots, report.html).
/// Returns the folder. Throws poise::Error after writing the folder if no design is feasible.
std::string run_optimization(const std::string& path, const studies::RunOptions& options);

}  // namespace poise::optimize
