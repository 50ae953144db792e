#pragma once
/// An optimization study (`poise optimize FILE.toml`, file format: optimization_spec.h).
/// Every evaluation runs the base study with the same seed and sample count (common random
/// numbers), so the objective is a smooth function of the design. Then the answer is made to
/// hold:
///   1. choices decided on fresh samples (choice_decision.h): a selection set picks, a
///      comparison set compares, with the equivalence margin;
///   2. the headline design checked on the comparison (fresh) set (fresh_check.h): verified,
///      or NOT verified, and then the nearest design that passes is searched by tightening the
///      failing constraints by their excess, and re-checked on a third independent set;
///   3. the optimum's own uncertainty: the headline combination's search repeated with
///      `replicates` independent seeds (the spread of each variable and of the objective), the
///      interval of each constraint on the search's own samples (binding ones marked), and the
///      answer rounded to what the spread supports;
///   4. the answer in one sentence (summary.json "answer", the terminal, the report's top).
/// Two objectives ([pareto]): the epsilon-constraint front, each point checked on fresh samples.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/run/study_runner.h"
#include "optimize/choice_decision.h"
#include "optimize/design_search.h"
#include "optimize/fresh_check.h"
#include "optimize/optimization_spec.h"

namespace poise::optimize {

/// Exit statuses of `poise optimize`.
inline constexpr int kExitVerified = 0;      ///< an optimum that passed its fresh-sample check
inline constexpr int kExitRunFailed = 1;     ///< no feasible design, or the run failed
inline constexpr int kExitInvalidInput = 2;  ///< the files did not validate
inline constexpr int kExitNotVerified = 3;   ///< design not verified on fresh samples

struct OptimizationOutcome {
  std::vector<ChoiceResult> runs;     ///< one per combination of the choices (or one)
  std::size_t best = 0;               ///< the headline: index into runs (best on fresh samples)
  std::size_t optimization_pick = 0;  ///< best on the search's own samples
  bool feasible = false;
  std::string message;                         ///< why not, when infeasible
  std::map<std::string, std::string> optimum;  ///< overrides of the headline design
  FreshCheck check;                            ///< the headline's fresh-sample check (comparison set)
  bool verified = false;                       ///< check.verdict == passes
  nlohmann::json verification;                 ///< check as json
  nlohmann::json nearest;                      ///< when not verified: the nearest design that passes, or why none
  nlohmann::json spread;                       ///< replicates of the search: spread of variables and objective
  nlohmann::json binding;                      ///< constraints on the search's samples at the optimum, with intervals
  std::vector<std::map<std::string, std::string>> choices;  ///< the combinations, in order
  std::vector<ParetoPoint> pool;                            ///< every evaluation ([pareto] only)
  std::vector<std::size_t> front;                           ///< indices into pool, by increasing second objective
  nlohmann::json front_verification;                        ///< per front point: both objectives with 95% CIs
  nlohmann::json comparison;                                ///< choices decided on fresh samples (choice_decision.h)
  std::string answer;                                       ///< the answer in one sentence
  /// What the answer cost: design evaluations (each a base-study run) and the samples they
  /// simulated, searches, fresh sets and checks together; model_samples of the full model,
  /// fast_samples (in fast_evaluations) of the kind's fast model (search_model = "fast").
  std::size_t design_evaluations = 0;
  std::size_t model_samples = 0;
  std::size_t fast_evaluations = 0;
  std::size_t fast_samples = 0;
  /// search_model = "fast": the headline design on its fresh samples under both models
  /// (objective and constraint figures, their differences), and what the fast model leaves out.
  nlohmann::json fast_model;
};

/// A statistic of `values` with a bootstrap 95% percentile interval (`resamples` resamples,
/// deterministic in `seed`): {value, lo, hi}.
nlohmann::json statistic_with_ci(const std::vector<double>& values, const std::string& statistic, std::uint64_t seed,
                                 int resamples = 1000);

/// Runs the optimization and the checks. Does not write anything.
OptimizationOutcome optimize(const OptimizationSpec& spec, int threads, bool progress);

/// What run_optimization produced.
struct OptimizationRun {
  std::string dir;  ///< the result folder
  int exit_status = kExitVerified;
  std::string answer;
};

/// Runs it and writes results/<name>/<run id>/ (history.csv, summary.json, plots, report.html).
/// `seed` (if set) replaces the file's [optimization] seed. Throws poise::Error after writing
/// the folder if no design is feasible.
OptimizationRun run_optimization(const std::string& path, const engine::RunOptions& options,
                                 std::optional<std::uint64_t> seed = std::nullopt);

}  // namespace poise::optimize
