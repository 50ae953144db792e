#pragma once
/// A balancing campaign analysed (poise balance, Python's poise.balance): the influence
/// coefficients calibrated on every run with known masses (check runs left out), the rotor's own
/// unbalance, the least-squares correction and the readings it leaves, and the unbalance of each
/// run of unknown masses and of each check run, all with their 95% regions
/// (estimators/balancing_prediction.h). A check run's answer is compared with its known masses.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "balancing/campaign.h"
#include "estimators/balancing_prediction.h"

namespace poise::balancing {

/// The answer for one declared run that the calibration did not use.
struct RunAnswer {
  std::string name;
  bool check = false;
  std::size_t readings = 0;                                ///< rows averaged
  estimators::PlaneAnswers unbalance;                      ///< per plane, g at its radius; static/couple below
  std::optional<std::vector<estimators::Phasor>> applied;  ///< a check run's masses
};

struct CampaignAnalysis {
  estimators::InfluenceCalibration calibration;
  estimators::Correction correction;  ///< the plain least-squares correction
  estimators::PlaneAnswers correction_masses, initial_unbalance;
  std::vector<estimators::PhasorInterval> residual_readings;
  std::vector<RunAnswer> runs;
  /// Static and couple unbalance: "g mm" where every plane's radius is given, else "g" (at the
  /// planes' radii), and the factor from the estimators' figures (g m or g) to that unit.
  std::string moment_unit;
  double moment_factor = 1.0;
  std::string answer;  ///< the campaign's answer in one sentence
};

/// Throws poise::Error when the campaign cannot be calibrated (too few runs, planes not
/// separated, fewer sensors than planes).
CampaignAnalysis analyse_campaign(const BalancingCampaign& c);

/// The analysis as `poise balance --json` prints it.
nlohmann::json analysis_json(const BalancingCampaign& c, const CampaignAnalysis& a);

/// "15.33 g @ 2.9 deg" and, with a region, " (95%: +- 1.2 g)".
std::string phasor_text(const estimators::PhasorInterval& z, const std::string& unit, double factor = 1.0);

/// An angle in degrees in [0, 360).
double degrees(const estimators::Phasor& z);

}  // namespace poise::balancing
