#pragma once
/// Answers of a calibrated influence-coefficient model with their 95% confidence regions: the
/// unbalance of a run (the masses that explain its readings), the rotor's own unbalance, the
/// least-squares correction, static and couple unbalance, and the readings after correction.
///
/// Every answer y is a smooth function of the calibration's coefficients beta_s = [a_s, h_s1..]
/// (one row per sensor) and, for a run's unbalance, of the run's mean readings v_s. Their errors
/// are circular complex normal and independent between sensors (the calibration's assumption):
///   Cov(beta_s) = s_s^2 (X^H X)^-1,   Var(v_s) = s_s^2 / n   (n readings averaged),
/// so that each answer's error, to first order, is J_s (beta_s, v_s errors) summed over sensors
/// with J the Jacobian (central differences of the real and imaginary parts). Its covariance is
/// the 2 x 2 real matrix S = sum_s s_s^2 A_s of (Re, Im). With s_s^2 estimated on
/// nu_s = 2 (runs - planes - 1) degrees of freedom, the effective degrees of freedom are
/// Welch-Satterthwaite's along the principal axis of S that gives the fewer, and the 95% region is the ellipse
///   d^T S^-1 d <= 2 F(0.95; 2, nu),
/// Hotelling's form for a two-part estimate (e.g. Montgomery, Design and Analysis of
/// Experiments, 2017, sec. 10.6, for the calibration (inverse prediction) case). Its coverage is
/// tested on simulated campaigns (tests/estimators/balancing_prediction_test.cc).
///
/// Static and couple unbalance of two planes (ISO 21940-2's terms, for a rigid rotor): the static
/// unbalance is the resultant U_1 + U_2 and the couple unbalance the pair +-(U_1 - U_2)/2, each
/// in mass times radius where the planes' radii are given.
#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "estimators/influence_coefficients.h"

namespace poise::estimators {

/// A complex answer and, when the calibration has degrees of freedom, its 95% confidence ellipse.
struct PhasorInterval {
  Phasor value;
  /// Covariance of (Re, Im): xx, xy, yy; absent without degrees of freedom.
  std::optional<std::array<double, 3>> covariance;
  double dof = 0.0;  ///< effective degrees of freedom of the covariance
  double level = 0.95;
  /// The ellipse's largest half axis (a circle of this radius about the value holds it).
  std::optional<double> radius() const;
  /// Whether z lies in the ellipse (false without one).
  bool contains(const Phasor& z) const;
};

/// One answer per plane, and for two planes the static and the couple unbalance.
struct PlaneAnswers {
  std::vector<PhasorInterval> planes;
  std::optional<PhasorInterval> static_unbalance, couple_unbalance;
};

/// The masses (per plane, at its radius) that explain the mean of `readings` (n >= 1 readings of
/// one run) beyond the calibrated rotor's own readings: least squares over the sensors.
/// `radii` (m, one per plane, 0 where unknown) scale static and couple to mass times radius
/// (g m) when every radius is known; otherwise they are in g at the planes' radii.
PlaneAnswers unbalance_answers(const InfluenceCalibration& c, const std::vector<std::vector<Phasor>>& readings,
                               const std::vector<double>& radii);

/// The rotor's own unbalance as calibrated (the masses that its readings a come from).
PlaneAnswers initial_unbalance_answers(const InfluenceCalibration& c, const std::vector<double>& radii);

/// The least-squares correction (correction(c).masses) with its regions.
PlaneAnswers correction_answers(const InfluenceCalibration& c, const std::vector<double>& radii);

/// The reading each sensor will show after the correction is added: its value and a 95%
/// prediction region (the calibration's uncertainty and one new reading's noise).
std::vector<PhasorInterval> residual_reading_answers(const InfluenceCalibration& c);

}  // namespace poise::estimators
