#pragma once
/// The searches of an optimization: one design evaluated (the base study run with the design's
/// overrides on the search's samples: common random numbers), scored against the objective
/// and the constraints, and the NLopt searches of one combination of the choices (the
/// objective; with [pareto], the second objective and the epsilon-constrained ones).
///
/// Failures count: an evaluation in which more than the base study's [sampling]
/// max_failure_share of the samples failed is a failed evaluation (ok = false) with the share
/// and the first reason; below it the statistics are taken on the samples that ran, and the
/// share is kept with the evaluation (history.csv).
#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "engine/kind_interface/study_evaluation.h"
#include "optimize/optimization_spec.h"
#include "optimize/optimizer.h"

namespace poise::optimize {

/// Progress on stderr and an ETA over the whole run, the fresh-sample checks included:
/// the work is counted in samples evaluated, each step adds what it plans.
class RunProgress {
 public:
  explicit RunProgress(bool on) : on_(on), start_(std::chrono::steady_clock::now()) {}
  void plan(double samples) { planned_ += samples; }
  /// `samples` done (of the kind's fast model if `fast`); prints "  <line>  (elapsed, ETA <=
  /// ...)" when on.
  void step(double samples, const std::string& line, bool fast = false);
  bool on() const { return on_; }
  /// What the run spent: design evaluations and the samples they simulated, of the full model
  /// and of the fast one.
  double done() const { return done_; }
  std::size_t evaluations() const { return evaluations_; }
  std::size_t full_evaluations() const { return evaluations_ - fast_evaluations_; }
  std::size_t fast_evaluations() const { return fast_evaluations_; }
  double full_samples() const { return done_ - fast_samples_; }
  double fast_samples() const { return fast_samples_; }

 private:
  bool on_;
  std::chrono::steady_clock::time_point start_;
  double planned_ = 0.0, done_ = 0.0, fast_samples_ = 0.0;
  std::size_t evaluations_ = 0, fast_evaluations_ = 0;
};

/// What the searches keep of each design evaluated.
struct ScoredDesign {
  Evaluation primary;        ///< objective and constraint values (c <= 0 met)
  double second = NAN;       ///< [pareto] statistic
  double failure_share = 0;  ///< failed samples / samples
};

/// Samples one search plans to draw: its evaluations times the samples per evaluation (a
/// Pareto study's front adds its points and the two ends when pareto is set).
double planned_search_samples(const OptimizationSpec& spec, bool pareto);

/// One evaluated design against the spec: failure share, objective, constraints (the
/// statistic or its stated confidence bound, minus the limit).
ScoredDesign score_design(const OptimizationSpec& spec, const std::vector<double>& x, const engine::McResult& e);

/// The objective of an evaluation: the statistic of its output, or the sum of the variables.
double objective_value(const OptimizationSpec& spec, const std::vector<double>& x, const engine::McResult& e);

/// The figure a constraint is stated on (statistic or its bound) from its value c.
double constraint_figure(const Requirement& r, double c);

/// Model and study overrides of a design: [overrides], the choice, the variables.
std::map<std::string, std::string> overrides_of(const OptimizationSpec& spec, const std::vector<double>& x,
                                                const std::map<std::string, std::string>& choice);

/// One evaluation of any search (for the Pareto front).
struct ParetoPoint {
  std::size_t choice = 0;  ///< index of the combination of choices
  std::string search;      ///< "objective", "second", "epsilon <level>"
  std::vector<double> x;   ///< variables in their units
  double objective = NAN, second = NAN;
  bool feasible = false;  ///< ok and every constraint met (the epsilon bound aside)
};

/// The searches of one combination of the choices with one seed.
struct ChoiceResult {
  std::map<std::string, std::string> choice;  ///< parameter -> value
  std::uint64_t seed = 0;
  Result result;                                        ///< the objective's search, in the variables' units
  std::map<std::vector<double>, ScoredDesign> designs;  ///< every design evaluated
};

struct SearchSetup {
  std::size_t choice_index = 0;
  std::uint64_t seed = 0;
  std::vector<double> start;
  bool pareto = false;                       ///< also the second objective and epsilon searches
  std::vector<ParetoPoint>* pool = nullptr;  ///< where the Pareto evaluations go
  std::string label;                         ///< progress prefix ("positions = 18", "replicate 2")
};

/// Runs the searches of one combination of the choices.
ChoiceResult search_choice(const OptimizationSpec& spec, const std::map<std::string, std::string>& choice,
                           const SearchSetup& setup, int threads, RunProgress& progress);

}  // namespace poise::optimize
