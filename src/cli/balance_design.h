#pragma once
/// The real machine beside its design study (`[design]` of a balancing campaign): the study is
/// run in memory (its kind's evaluate, the optimizer's path) and each real figure of the
/// campaign (ISO 21940-21's URR or U_mar, balancing/iso_figures.h) is placed in the simulated
/// distribution of the output it names: the share of simulated machines at or below it, and
/// whether it lies within their central 95%. A real figure outside says the machine does not
/// behave as its design study predicts (the model tests say which effect the readings show).
#include <optional>
#include <string>
#include <vector>

#include "balancing/campaign.h"
#include "balancing/campaign_analysis.h"

namespace poise::cli {

using balancing::DesignComparison;

/// Runs the design study and compares (empty without [design]). Throws poise::Error for a study
/// that cannot be run or an output it does not have (with its outputs).
std::vector<DesignComparison> compare_with_design(const balancing::BalancingCampaign& c,
                                                  const balancing::CampaignAnalysis& a, int threads);

/// compare_with_design as analyse_campaign's runner.
balancing::DesignRunner design_runner(int threads);

}  // namespace poise::cli
