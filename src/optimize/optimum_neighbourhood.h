#pragma once
// The optimum's neighbourhood, after the decision (optimization_study.cc): how far independent
// searches spread, how close each constraint is at the optimum, and when the fresh check did
// not pass, the nearest design that does.
#include "optimize/choice_decision.h"
#include "optimize/design_search.h"
#include "optimize/optimization_study.h"

namespace poise::optimize {

/// The optimum's own uncertainty: the search repeated with independent seeds (out.spread).
void measure_spread(const OptimizationSpec& spec, OptimizationOutcome& out, const ChoiceResult& best, int threads,
                    RunProgress& progress);

/// Each constraint at the optimum on the search's own samples, with its interval (out.binding).
void constraints_at_optimum(const OptimizationSpec& spec, OptimizationOutcome& out, const ChoiceResult& best,
                            int threads, RunProgress& progress);

/// Not verified: the nearest design that passes, by tightening what failed by its excess.
void find_nearest_design(const OptimizationSpec& spec, OptimizationOutcome& out, const ChoiceResult& best, int threads,
                         RunProgress& progress);

}  // namespace poise::optimize
