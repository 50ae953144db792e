#pragma once
/// The real machine beside its design study (`[design]` of a balancing campaign): the study is
/// run in memory (its kind's evaluate, the optimizer's path) and each real figure of the
/// campaign (ISO 21940-21's URR or U_mar, balancing/iso_figures.h, or an influence coefficient's
/// magnitude) is placed in the simulated distribution of the output it names: the share of
/// simulated machines at or below it, and whether it lies within their central 95%. A real
/// figure outside says the machine does not behave as its design study predicts (the model tests
/// say which effect the readings show). With [design.calibrate], a model key is fitted to the
/// influence figures (cli/balance_calibration.h).
#include <string>
#include <vector>

#include "balancing/campaign.h"
#include "balancing/campaign_analysis.h"
#include "core/units.h"
#include "engine/kind_interface/output_spec.h"
#include "engine/results/mc_result.h"

namespace poise::cli {

using balancing::DesignComparison;

/// The dimension a study's output must have to be compared with `figure` ("urr", "umar" or
/// "influence": the campaign's reading per unbalance).
units::Dimension figure_dimension(const balancing::BalancingCampaign& c, const std::string& figure);

/// A real influence coefficient's magnitude and its standard error, SI (reading per kg m).
struct RealCoefficient {
  double value = 0.0, se = 0.0;
};
/// |h| of the comparison's sensor and plane from the calibration. Throws poise::Error where the
/// plane has no radius.
RealCoefficient real_influence(const balancing::BalancingCampaign& c, const balancing::CampaignAnalysis& a,
                               const balancing::DesignCompare& k);

/// Places the campaign's figures in the simulated machines `sim` of the study (outputs: its
/// kind's). Throws poise::Error for an output of the wrong unit or without samples.
std::vector<DesignComparison> compare_with_design(const balancing::BalancingCampaign& c,
                                                  const balancing::CampaignAnalysis& a, const engine::McResult& sim,
                                                  const std::vector<engine::OutputSpec>& outputs);

/// The campaign's design study run and compared (and calibrated), as analyse_campaign's runner.
/// Throws poise::Error for a study that cannot be run or an output it does not have.
balancing::DesignRunner design_runner(int threads);

}  // namespace poise::cli
