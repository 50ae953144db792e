#pragma once
// `poise optimize OPT.toml`: design and test-plan optimization over a Monte Carlo study
// (optimize/optimization_study.h).
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>

namespace poise::cli {

using OptimizeHandler = std::function<std::optional<int>()>;

OptimizeHandler add_optimize_command(CLI::App& app);

}  // namespace poise::cli
