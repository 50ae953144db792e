#pragma once
/// The folder of `poise balance CAMPAIGN --out DIR`: balance.json (what --json prints) and
/// report.html, made from the typed analysis (no JSON read back): the answer first, the
/// correction (and its split onto holes), the readings beside the fitted model in the complex
/// plane, the vibration before and after the correction, the influence coefficients, the rotor's
/// own unbalance, the runs left out of the calibration, the tests of the linear model, and the
/// other speeds. Figures are gnuplot SVG set inline (one self-contained file).
#include <filesystem>
#include <string>

#include "balancing/campaign.h"
#include "balancing/campaign_analysis.h"

namespace poise::balancing {

/// report.html's text; figures are made in `dir` (a note replaces one gnuplot cannot draw).
std::string balance_report_html(const BalancingCampaign& c, const CampaignAnalyses& a,
                                const std::filesystem::path& dir);

/// Writes DIR (created; refused with poise::UsageError if it already holds balance.json).
void write_balance_folder(const std::filesystem::path& dir, const BalancingCampaign& c, const CampaignAnalyses& a);

}  // namespace poise::balancing
