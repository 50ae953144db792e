#pragma once
/// A model key of a balancing campaign's design study fitted to the real machine's influence
/// coefficients ([design.calibrate] of the campaign, balancing/campaign.h).
///
/// For a value v of the key (a model override, range [low, high]) the study runs `samples`
/// machines with the study's seed (common random numbers: the same draws for every v, so the
/// objective is smooth in v). The real machine is one machine as built: its figures (the
/// [[design.compare]] tables of figure "influence", |h_k| from the campaign's calibration with
/// standard error se_k) scatter about the study's means by the machines' own covariance. So
///   chi2(v) = r' S^-1 r,  r_k = mean_k(v) - |h_k|,
///   S = (1 + 1/n) cov(v) + diag(se_k^2)
/// with mean and cov the study's mean and covariance of those outputs over its n machines (the
/// 1/n: the error of its mean). Brent's method (Boost's brent_find_minima) minimises chi2 on the
/// range; the value's standard error is 1 / sqrt(g' S^-1 g), g the means' slopes by central
/// differences (1% of the range). chi2 after the fit against its dof = figures - 1 says whether the
/// study explains the machine with this key at all. Only magnitudes are fitted: the phases depend
/// on where each instrument puts its reference mark. Coverage of value +- 1.96 se over simulated
/// machines of a known value: tests/cli/balance_calibration_test.cc.
#include "balancing/campaign.h"
#include "balancing/campaign_analysis.h"
#include "engine/results/mc_result.h"
#include "engine/study_files/study_config.h"

namespace poise::cli {

/// `as_is`: the study as its files give it (the figures' "before"). Throws poise::Error where
/// the study cannot be run at the range's values (an unknown key, a value the model refuses).
balancing::DesignCalibration calibrate_design(const balancing::BalancingCampaign& c,
                                              const balancing::CampaignAnalysis& a, const engine::StudyConfig& cfg,
                                              const engine::McResult& as_is, int threads);

}  // namespace poise::cli
