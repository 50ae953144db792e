#pragma once
/// `poise fit DATA.csv [--json]`: least-squares sine fit (Yang et al. 2015, Eq. 22) of a
/// measured static unbalance torque table; see `poise fit --help` and
/// estimators/sine_fit.h, estimators/torque_table.h.
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>

namespace poise::cli {

/// Runs `poise fit` if it was the subcommand given: returns its exit status (0 success,
/// 2 invalid input, with the message on stderr), or nullopt when another subcommand was given.
using FitHandler = std::function<std::optional<int>()>;

/// Registers the `fit` subcommand on app (before app is parsed). Call the returned handler
/// once app has parsed the command line.
FitHandler add_fit_command(CLI::App& app);

}  // namespace poise::cli
