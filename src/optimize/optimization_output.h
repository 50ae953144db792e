#pragma once
/// The result folder of `poise optimize`: history.csv (every evaluation, constraints and
/// choices by name, failure share), pareto.csv, summary.json (with "answer" and the
/// fresh-sample verdict), plots and report.html (opening with the answer).
#include "optimize/optimization_study.h"

namespace poise::optimize {

/// Runs optimize() and writes the folder. Prints the answer on stdout unless quiet. Throws
/// poise::Error after writing the folder if no design is feasible.
OptimizationRun write_optimization(const OptimizationSpec& spec, const engine::RunOptions& options);

}  // namespace poise::optimize
