#pragma once
/// `poise balance CAMPAIGN.toml [--json] [--out DIR]`: a balancing machine's or a field balance's
/// readings analysed (balancing/campaign_analysis.h). See `poise balance --help` and
/// balancing/campaign.h.
#include <functional>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "balancing/campaign.h"
#include "balancing/campaign_analysis.h"

namespace poise::cli {

/// A campaign read and analysed, its design study run where it names one (cli/balance_design.h),
/// and with `out` its folder written (balancing/balance_report.h): what the command and Python's
/// poise.balance both do. Throws as the reading and analysis do; UsageError for a folder that
/// cannot be written.
struct BalanceResult {
  balancing::BalancingCampaign campaign;
  balancing::CampaignAnalyses analyses;
};
BalanceResult balance_campaign(const std::string& path, const std::string& out);

using BalanceHandler = std::function<std::optional<int>()>;
/// Registers the `balance` subcommand on app; the handler runs it once app has parsed.
BalanceHandler add_balance_command(CLI::App& app);

}  // namespace poise::cli
