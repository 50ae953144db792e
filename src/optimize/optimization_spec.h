#pragma once
/// The optimization file (`poise optimize FILE.toml`): design variables (model keys with
/// bounds), an objective (a statistic of an output of a base Monte Carlo study, or the sum
/// of design variables such as spans), constraints (statistics, or a confidence bound of one,
/// with at_least / at_most), optional discrete choices enumerated around the continuous
/// search, the NLopt algorithm, replicates of the search, and the fresh-sample check.
///
///   [optimization]  name, study (base study file, relative to this file), title, notes,
///                   samples, seed, algorithm, max_evaluations, xtol_rel,
///                   search_model ("full", or "fast": the searches on the kind's fast model,
///                   the fresh-sample checks on the full one),
///                   replicates (independent searches with other seeds: the optimum's spread),
///                   replicate_size (randomized replicates of the lhs / sobol design, for
///                   intervals that cover; default the base study's [sampling] replicate_size)
///   [[variable]]    parameter (dotted model key), lower, upper, start ("<number> <unit>")
///   [[choice]]      parameter, values = ["...", ...]      (discrete, enumerated)
///   [objective]     output + statistic, or variable_sum = ["key", ...] (minimized)
///   [[constraint]]  output, statistic, at_least = x | at_most = x  (in the output's unit),
///                   bound = "upper95" | "lower95" | ... (a chance constraint with confidence:
///                   the one-sided bound of the statistic at that confidence must meet the limit;
///                   at_most takes an upper bound, at_least a lower one), name (for history.csv)
///   [pareto]        output, statistic, points: a second objective (minimized)
///   [overrides]     "key" = "value": model or study keys set for every evaluation
///   [verification]  samples, seed, equivalence_margin ("5%" of the better choice's figure, or
///                   a number in the objective's unit), max_nearest_rounds
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "engine/results/confidence_bound.h"
#include "engine/study_files/study_config.h"
#include "optimize/optimizer.h"

namespace poise::optimize {

/// The bounds and intervals live in the engine (engine/results/confidence_bound.h): requirements'
/// verdicts use the same ones.
using engine::bound_supported;
using engine::BoundSide;
using engine::BoundSpec;
using engine::describe;
using engine::Interval;
using engine::interval;
using engine::one_sided_bound;
using engine::parse_bound;
using engine::sample_set;
using engine::SampleSet;
using engine::to_string;

struct DesignVariable {
  std::string parameter;                         ///< dotted model key
  std::string unit;                              ///< unit the bounds were written in ("mm"); "" if dimensionless
  double lower = 0.0, upper = 0.0, start = 0.0;  ///< in that unit
};

struct Choice {
  std::string parameter;
  std::vector<std::string> values;
};

struct Requirement {
  std::string name;  ///< "los_max_px.p99_73.upper95" unless the file names it
  std::string output, statistic;
  std::optional<double> at_least, at_most;
  BoundSpec bound;  ///< side kNone: the statistic's point value must meet the limit

  double limit() const { return at_least ? *at_least : *at_most; }
  /// "p99.73 of los_max_px (upper 95% bound) <= 1"
  std::string describe() const;
};

struct ParetoSpec {
  std::string output, statistic;  ///< the second objective (minimized)
  int points = 3;                 ///< epsilon levels between the two single-objective optima
};

struct OptimizationSpec {
  std::string file, name, title, notes;
  engine::StudyConfig base;                         ///< the base study (replicate_size as the optimization sets it)
  std::map<std::string, std::string> output_units;  ///< each output's declared unit (its kind's)
  std::size_t samples = 64;
  std::uint64_t seed = 1;
  Algorithm algorithm = Algorithm::kCobyla;
  int max_evaluations = 100;
  double xtol_rel = 1e-3;
  int replicates = 1;  ///< searches with independent seeds (1: the search alone)
  /// search_model = "fast": the searches run the kind's fast model (StudyKind::fast_model,
  /// described in fast_model_text); every fresh-sample check, and so the exit status, runs the
  /// full model. "full" (the default): the full model throughout.
  bool fast_search = false;
  std::string fast_model_text;
  std::vector<DesignVariable> variables;
  std::vector<Choice> choices;
  std::string objective_output, objective_statistic;  ///< empty output: variable_sum
  std::vector<std::string> variable_sum;
  std::vector<Requirement> constraints;
  std::optional<ParetoSpec> pareto;
  std::map<std::string, std::string> overrides;  ///< [overrides], under variables and choices
  std::size_t verification_samples = 256;
  std::uint64_t verification_seed = 2;
  /// Equivalence margin of the choices: relative (0.05 for "5%") or absolute in the
  /// objective's unit.
  double equivalence_margin = 0.05;
  bool equivalence_relative = true;
  std::string equivalence_margin_text = "5%";
  int max_nearest_rounds = 3;  ///< tightening rounds to find the nearest design that passes

  double max_failure_share() const { return base.max_failure_share; }
  /// The base study as the searches run it: the fast model with search_model = "fast".
  engine::StudyConfig search_study() const {
    engine::StudyConfig c = base;
    c.fast_model = fast_search;
    return c;
  }
  /// The seed of search replicate r (r = 0: `seed`), the selection set and the re-check set:
  /// all derived, distinct from each other and from the verification seed.
  std::uint64_t replicate_seed(int r) const;
  std::uint64_t selection_seed() const;
  std::uint64_t recheck_seed() const;
};

/// Loads and validates the file, its base study and that the outputs exist. Throws
/// engine::ValidationError (file, line, key, value, expected).
OptimizationSpec load_optimization(const std::string& path);

/// "positions = 18, placement = back_and_forth": each key by its shortest dotted suffix that
/// the other keys do not share ("yaw.perpendicularity.tolerance_is" beside its pitch twin
/// stays whole); "-" if empty.
std::string choice_label(const std::map<std::string, std::string>& choice);
/// The label of one key among `keys` (as in choice_label).
std::string choice_key_label(const std::string& key, const std::vector<std::string>& keys);

/// The override text of a value in a unit ("131.2 mm").
std::string value_text(double value, const std::string& unit);

}  // namespace poise::optimize
