#pragma once
/// `poise simulate-record` and `poise diagnose-record`: the time-series level of the
/// residual diagnosis (one turntable position: time, drive current, gimbal angle).
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>

namespace poise::cli {

/// Registers both subcommands; the returned handler runs whichever was given and returns
/// its exit status, or nothing if neither was.
std::function<std::optional<int>()> add_record_commands(CLI::App& app);

}  // namespace poise::cli
