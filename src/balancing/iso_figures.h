#pragma once
/// ISO 21940-21 machine figures from a real proving-rotor campaign, read from the check runs of a
/// calibrated machine (the same definitions as the balancing-machine kind's virtual tests,
/// kinds/balancing_machine/balancing_iso_tests.h, which state where they come from):
///
///   * URR per check run and plane that carries a test mass: the machine's indication of the
///     known test unbalance T (the check run's unbalance relative to the bare rotor, D) against
///     T: URR = 1 - |D - T| / |T|. Its 95% interval follows from D's 95% region (its largest half
///     axis rho): [1 - (|D - T| + rho) / |T|, 1 - max(0, |D - T| - rho) / |T|], conservative.
///   * U_mar per plane from the check runs marked `umar = true` (test masses in both planes moved
///     together through positions): the indicated amount X_k = |U_0 + D_k| (the bare rotor's own
///     unbalance U_0 plus the test masses'), U_mar = (X_max - X_min) / 2 times the plane's radius.
///     Its interval widens and narrows each X by its region's half axis (conservative).
#include <optional>
#include <string>
#include <vector>

#include "balancing/campaign.h"
#include "balancing/campaign_analysis.h"

namespace poise::balancing {

struct IsoUrrFigure {
  std::string run, plane;
  double urr = 0.0;
  std::optional<double> lower, upper;  ///< 95%, where the region exists
};

struct IsoUmarFigure {
  std::string plane;
  std::size_t positions = 0;
  double umar = 0.0;                   ///< g mm where the plane's radius is given, else g
  std::optional<double> lower, upper;  ///< 95%
  std::string unit;
};

struct IsoFigures {
  std::vector<IsoUrrFigure> urr;
  std::vector<IsoUmarFigure> umar;
};

/// The figures of one speed's analysis (empty without check runs).
IsoFigures iso_figures(const BalancingCampaign& c, const CampaignAnalysis& a);

}  // namespace poise::balancing
