#pragma once
/// `poise budget BUDGET.toml [--json] [--out DIR]`: a reviewer's error budget recomputed line
/// by line (budget/budget_check.h), its verdicts and likely slips, the combined figure at the
/// requirement's confidence, and the Monte Carlo of the model's exact chain beside it
/// (budget_monte_carlo.h). See `poise budget --help`.
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace poise::cli {

/// Runs `poise budget` if it was the subcommand given: its exit status (0 success, 2 invalid
/// input, 1 other failure), or nullopt when another subcommand was given.
using BudgetHandler = std::function<std::optional<int>()>;

/// The budget file checked: the `--json` object (lines, groups, combined, monte_carlo,
/// answer, ...); the Monte Carlo's values go to `mc_values` when given; `progress` says on
/// stderr what the Monte Carlo runs. Throws
/// engine::ValidationError or UsageError for invalid input, poise::Error otherwise.
nlohmann::json check_budget_file(const std::string& path, std::vector<double>* mc_values = nullptr,
                                 bool progress = true);

/// Registers the `budget` subcommand on app (before app is parsed).
BudgetHandler add_budget_command(CLI::App& app);

}  // namespace poise::cli
