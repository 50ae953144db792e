#pragma once
/// `poise fit DATA.csv [--json]`: least-squares sine fit (Yang et al. 2015, Eq. 22) of a
/// measured static unbalance torque table; see `poise fit --help` and
/// estimators/sine_fit.h, estimators/torque_table.h.
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/column_options.h"

namespace poise::cli {

/// Runs `poise fit` if it was the subcommand given: returns its exit status (0 success,
/// 2 invalid input, with the message on stderr), or nullopt when another subcommand was given.
using FitHandler = std::function<std::optional<int>()>;

/// Registers the `fit` subcommand on app (before app is parsed). Call the returned handler
/// once app has parsed the command line.
FitHandler add_fit_command(CLI::App& app);

/// `poise fit --json`: the sine fit of a measured torque table (the file's columns named as
/// `columns` maps them), as the command prints it. Throws poise::Error for a file it refuses.
nlohmann::json fit_torque_table(const std::string& path, const ColumnOptions& columns);

}  // namespace poise::cli
