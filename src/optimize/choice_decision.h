#pragma once
/// Discrete choices as decisions. Each combination of the choices has its best continuous
/// design from the search (on the search's samples). Two independent fresh sets follow (with
/// search_model = "fast", the selection set runs the fast model and only the finalists, the
/// selection pick and each choice value's best combination, run the comparison set, on the
/// full model):
///   selection set   picks: the headline (the combination best on fresh samples among those
///                   meeting their constraints there) and, for each value of a choice
///                   parameter, its best combination;
///   comparison set  compares what was picked, on samples that took no part in picking it:
///                   the objective with its 95% interval, every constraint re-checked, the
///                   paired difference to the headline (bootstrap over the same units) and
///                   the equivalence verdict with the study's margin.
/// Equivalence within a margin m (two one-sided tests at 2.5% each, i.e. the 95% interval of
/// the difference inside [-m, +m]) is shown, or NOT shown with the side whose end exceeds m.
/// The bootstrap share of resamples in which the headline stays ahead is reported as what it
/// is, a bootstrap share, not a probability that it is better.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "optimize/design_search.h"
#include "optimize/fresh_check.h"

namespace poise::optimize {

struct Difference {
  double value = NAN;            ///< stat(a) - stat(b)
  std::optional<double> lo, hi;  ///< bootstrap 95% percentile interval
  double share_b_ahead = NAN;    ///< bootstrap share of resamples with stat(a) > stat(b)
  bool paired = false;
};

/// Bootstrap of stat(a) - stat(b): paired (the same resampled units) when a and b come from
/// the same units (equal ok_index), otherwise each resampled on its own.
Difference difference(const std::vector<double>& a, const std::vector<std::size_t>& a_units,
                      const std::vector<double>& b, const std::vector<std::size_t>& b_units, const std::string& stat,
                      std::uint64_t seed, int resamples = 2000);

struct Equivalence {
  double margin = 0.0;  ///< absolute, in the objective's unit
  bool shown = false;   ///< the whole interval within [-margin, +margin]
  bool worse = false;   ///< the whole interval above +margin (a is worse beyond the margin)
  bool better = false;  ///< the whole interval below -margin
  std::string exceeds;  ///< "upper", "lower", "both" or "" (which end leaves the margin)
};
Equivalence equivalence(const Difference& d, double margin);

/// "difference -0.01 [-0.06, +0.13] mN*m, which exceeds the 5% margin (0.055 mN*m) on the upper
/// side, so equivalence is NOT shown"
std::string equivalence_clause(const Difference& d, const Equivalence& e, const std::string& unit,
                               const std::string& margin_text, const std::string& subject = "it");

/// One combination on the fresh sets.
struct ChoiceOnFresh {
  std::size_t run = 0;
  FreshCheck selection, comparison;
  bool compared = false;  ///< on the comparison set (a finalist; every combination without a fast search)
};

struct ChoiceDecision {
  std::vector<ChoiceOnFresh> fresh;       ///< feasible combinations, in run order
  std::size_t headline = 0;               ///< index into runs
  bool headline_met_on_selection = true;  ///< false: none met its constraints on the selection set
  nlohmann::json json;                    ///< choices, by_parameter (with equivalence), sets
  std::string sentence;                   ///< the decision in words ("" without a choice parameter)
};

/// Evaluates every feasible combination's design on both fresh sets and decides.
ChoiceDecision decide_choices(const OptimizationSpec& spec, const std::vector<ChoiceResult>& runs,
                              std::size_t optimization_pick, int threads, RunProgress& progress);

}  // namespace poise::optimize
