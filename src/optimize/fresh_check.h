#pragma once
/// The fresh-sample check of a design: the base study run at the design with random numbers
/// the search never saw, each constraint judged with its interval.
///
///   passes     the whole 95% interval of the statistic meets the limit (a constraint stated
///              on a confidence bound: that bound, on the fresh samples, meets it);
///   straddles  the point value meets the limit but the interval (bound) crosses it, or the
///              interval's far end does not exist with this many samples;
///   fails      the point value misses the limit, or more than max_failure_share of the
///              samples failed.
/// min and max have no distribution-free interval on their far side: they are judged on the
/// sample extreme of the fresh samples (which, with more samples than the search, is the
/// stricter figure).
#include <optional>
#include <string>
#include <vector>
#include "core/number_text.h"

#include <nlohmann/json.hpp>

#include "engine/kind_interface/study_evaluation.h"
#include "engine/results/confidence_bound.h"
#include "optimize/optimization_spec.h"

namespace poise::optimize {

enum class Verdict { kPasses, kStraddles, kFails };
std::string to_string(Verdict v);  ///< "passes", "straddles the limit", "fails"

struct ConstraintCheck {
  Requirement requirement;      ///< a copy: a check outlives the spec it was made from
  std::string unit;             ///< of the requirement's output
  Interval interval;            ///< the statistic with its 95% interval
  std::optional<double> bound;  ///< the stated bound on these samples (bound constraints)
  bool stated_met = false;      ///< the figure as stated (value or bound) meets the limit
  Verdict verdict = Verdict::kFails;
};

struct FreshCheck {
  std::size_t samples = 0, failures = 0;
  std::uint64_t seed = 0;
  double failure_share = 0.0;
  bool failures_ok = true;
  std::optional<Interval> objective;  ///< objective statistic with its 95% interval (output objective)
  double objective_value = NAN;       ///< the objective (also for variable_sum)
  std::optional<Interval> second;     ///< [pareto]
  std::vector<ConstraintCheck> constraints;
  std::vector<double> objective_values;  ///< the objective output's values (for paired comparisons)
  std::vector<std::size_t> ok_index;
  Verdict verdict = Verdict::kFails;  ///< the worst of the constraints' and the failures'
  bool stated_met = false;            ///< every constraint met as stated, failures within the share

  /// "p99.73 of los_max_px 1.002 [0.974, 1.019] px (upper 95% bound 1.015) straddles <= 1"
  std::string describe_constraint(std::size_t k) const;
  /// The constraints that do not pass, described; "" if all pass.
  std::string problems() const;
  nlohmann::json to_json() const;
};

/// Checks the design that gave `e` (run with `samples`, `seed`) against spec's constraints.
FreshCheck check_design(const OptimizationSpec& spec, const std::vector<double>& x, const engine::McResult& e,
                        std::uint64_t seed);

/// {value, lo, hi, method}; an end that does not exist is left out.
nlohmann::json interval_json(const Interval& i);
/// "1.09 [1.02, 1.16] mN*m" (3 significant digits, "?" for a missing end).
std::string interval_text(const Interval& i, const std::string& unit);
/// The declared unit of an output of the optimization's study ("mN*m"); "" for a
/// dimensionless one.
std::string output_unit(const OptimizationSpec& spec, const std::string& output);
using poise::short_number;  // core/number_text.h

}  // namespace poise::optimize
