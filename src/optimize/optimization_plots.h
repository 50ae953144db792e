#pragma once
/// The figures of `poise optimize`'s report: gnuplot scripts and their data in the run's
/// plots/ folder (the page that shows them: engine/report/optimization_page.h).
#include <filesystem>
#include <string>
#include <vector>

#include "optimize/optimization_study.h"

namespace poise::optimize {

/// The objective's column name in history.csv and on the convergence axis
/// ("objective.<output>.<statistic>").
std::string objective_name(const OptimizationSpec& spec);

/// Writes plots/convergence.* and, for a Pareto study with a feasible design, plots/pareto.*;
/// returns the SVG files gnuplot made.
std::vector<std::string> optimization_plots(const OptimizationSpec& spec, const OptimizationOutcome& out,
                                            const std::filesystem::path& plots_dir);

}  // namespace poise::optimize
