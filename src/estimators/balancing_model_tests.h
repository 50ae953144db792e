#pragma once
/// Tests of the influence-coefficient model v = a + H w on a campaign's own readings: does the
/// machine read as the linear model says, and if not, which effect is missing? Each test adds
/// terms to the model and asks, sensor by sensor, whether they lower the residual more than
/// noise would (the extra-sum-of-squares F test of nested least-squares fits, complex: each
/// complex residual is two real degrees of freedom), the sensors' p-values combined by Fisher's
/// method (independent sensors, as the calibration assumes). A term found significant at level
/// alpha (Bonferroni over the tests that ran) is added: the residual of the readings and of the
/// check runs' readings are given before and after.
///
/// - Lack of fit against repeats: with repeated readings of a run, the residual of the linear
///   model against the repeats' own scatter (pure error): any departure from linearity.
/// - Amplitude nonlinearity (a mass ladder shows it): Ramsey's RESET term y_fit |y_fit|^2 per
///   sensor (a gain that changes with the vibration's size: a hardening or softening support,
///   a saturating sensor).
/// - Superposition: products w_p w_q of two planes' masses: do runs with masses in two planes
///   read as the sum of the single-plane responses?
/// - Phase sense: terms in the masses' mirror images conj(w). A campaign whose phases or
///   masses' angles count the other way reads as conj(w), not w; a declared sense that is wrong
///   is named when the mirror-image model fits and the declared one does not.
/// - Runout (a reading that does not follow the masses): with readings at two or more speeds, a
///   constant vector per sensor beside the rotor's unbalance response H(speed) u; one speed
///   cannot tell runout from unbalance.
/// - Sensor cross-talk is absorbed in the coefficients: a linear campaign cannot show it.
#include <optional>
#include <string>
#include <vector>

#include "estimators/influence_coefficients.h"

namespace poise::estimators {

struct ModelTest {
  std::string name;  ///< "lack of fit", "amplitude nonlinearity", "phase sense", "runout"
  bool ran = false;  ///< false: the campaign cannot separate it (see needs)
  bool significant = false;
  std::optional<double> p_value;
  std::string finding;  ///< what was found, in words
  std::string needs;    ///< where it could not run: the runs that would let it
  /// RMS of the calibration runs' residual readings and of the check runs' prediction errors,
  /// without the term and with it (the amplitude unit), where it ran.
  std::optional<double> residual_before, residual_after, check_before, check_after;
};

/// The tests of lack of fit, amplitude nonlinearity and phase sense on one speed's runs (the
/// calibration's: runs with known masses; check runs predicted).
std::vector<ModelTest> test_linear_model(const std::vector<BalancingRun>& runs, std::size_t planes);

/// The runout test on calibrations at two or more speeds (the rotor's own readings a at each
/// speed against one unbalance u through each speed's H), and the rotor's unbalance without the
/// runout where it is significant (found in `finding`).
ModelTest test_runout(const std::vector<InfluenceCalibration>& speeds);

/// The family level: 0.01 over the tests that ran (Bonferroni).
inline constexpr double kModelTestLevel = 0.01;

}  // namespace poise::estimators
