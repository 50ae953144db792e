#pragma once
/// `poise budget BUDGET.toml [--json] [--out DIR]`: a reviewer's error budget recomputed line
/// by line (budget/budget_check.h), its verdicts and likely slips, the combined figure at the
/// requirement's confidence, and the Monte Carlo of the model's exact chain beside it
/// (budget_monte_carlo.h). See `poise budget --help`.
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>

namespace poise::cli {

/// Runs `poise budget` if it was the subcommand given: its exit status (0 success, 2 invalid
/// input, 1 other failure), or nullopt when another subcommand was given.
using BudgetHandler = std::function<std::optional<int>()>;

/// Registers the `budget` subcommand on app (before app is parsed).
BudgetHandler add_budget_command(CLI::App& app);

}  // namespace poise::cli
