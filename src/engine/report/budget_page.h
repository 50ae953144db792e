#pragma once
/// report.html of `poise budget --out DIR`: self-contained (inline CSS and SVG, no script, no
/// file beside it). Every line and group with its inputs, recomputed and declared values,
/// verdict and likely slip; the combination; and one plot of the budget against the Monte
/// Carlo: the empirical CDF and histogram of the model's output with the budget's least and
/// greatest (at the lines' level and at the confidence), the Monte Carlo quantile with its 95%
/// interval, and the requirement.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace poise::engine {

/// The page, from the budget's JSON object (what `poise budget --json` prints). mc_sorted: the
/// Monte Carlo values in the budget's unit, sorted (empty without a model).
std::string budget_report_html(const nlohmann::json& j, const std::vector<double>& mc_sorted);

/// The plot alone (an <svg> element), for tests and for the report.
std::string budget_plot_svg(const nlohmann::json& j, const std::vector<double>& mc_sorted);

}  // namespace poise::engine
