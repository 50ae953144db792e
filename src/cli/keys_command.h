#pragma once
/// `poise keys [KIND] [--json]`: every key of a study kind's study and model files, generated
/// from the program's own reading (engine/study_files/study_keys.h); without KIND, the kinds.
#include <CLI/CLI.hpp>

#include <functional>
#include <optional>

namespace poise::cli {

using KeysHandler = std::function<std::optional<int>()>;
/// Registers the `keys` subcommand; the handler runs it when it was given (exit status).
KeysHandler add_keys_command(CLI::App& app);

/// The study kinds, one paragraph each (for `poise --help` and `poise keys`).
std::string study_kinds_text();

}  // namespace poise::cli
