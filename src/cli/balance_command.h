#pragma once
/// `poise balance CAMPAIGN.toml [--json]`: a balancing machine's or a field balance's readings
/// through the influence-coefficient method (estimators/influence_coefficients.h): the
/// coefficients with their standard errors, the planes' separation, the correction masses and the
/// residual they leave. See `poise balance --help` and cli/balance_campaign.h.
#include <functional>
#include <optional>

#include <CLI/CLI.hpp>

namespace poise::cli {

using BalanceHandler = std::function<std::optional<int>()>;
/// Registers the `balance` subcommand on app; the handler runs it once app has parsed.
BalanceHandler add_balance_command(CLI::App& app);

}  // namespace poise::cli
