#pragma once
/// The influence-coefficient method of balancing, from a campaign's readings: the 1X vibration
/// of each sensor (amplitude and phase, a complex number) on runs with known masses added in
/// known planes.
///
/// Model (linear in the masses; e.g. Goodman 1964, Trans. ASME J. Eng. Ind. 86:273; ISO 21940-13):
///   v[r][s] = a[s] + sum_p h[s][p] w[r][p]
/// with v the reading of sensor s on run r, w[r][p] = m e^{i theta} the mass added in plane p
/// on run r (mass, angle), a[s] the rotor's own reading (its initial unbalance's) and h[s][p] the
/// influence coefficient. Fitted per sensor by complex least squares over every run with known
/// masses (not one trial run); with more runs than 1 + planes, the residuals give standard errors
/// (circular complex normal errors: each part of an estimate has the sd sqrt(s^2 (X^H X)^-1_jj / 2),
/// s^2 = sum |e|^2 / (R - P - 1), and Student's t with 2 (R - P - 1) degrees of freedom; its
/// coverage is tested in tests/estimators/influence_coefficients_test.cc).
///
/// The correction w minimises sum_s |a[s] + sum_p h[s][p] w[p]|^2 (the least-squares correction
/// of Goodman 1964 over every sensor): w = -(H^H H)^-1 H^H a; the predicted residual vibration is
/// a + H w. The unbalance of a run with unknown masses (the rotor as it came) is
/// u = (H^H H)^-1 H^H (v - a).
#include <complex>
#include <optional>
#include <string>
#include <vector>

namespace poise::estimators {

using Phasor = std::complex<double>;

/// One reading of a run: its name, readings (one per sensor) and the masses it added (one per
/// plane; 0 where none), or no masses known (an unknown rotor's run). A check run has known
/// masses that the calibration leaves out: its unbalance is predicted and compared with them.
/// `declared` numbers the run (repeated readings of one run share it).
struct BalancingRun {
  std::string name;
  std::vector<Phasor> readings;
  std::optional<std::vector<Phasor>> masses;
  bool check = false;
  std::size_t declared = 0;
  std::optional<double> speed_rpm;  ///< where the readings give it
};

/// A complex estimate with its standard error (the sd of each of its parts), if any.
struct PhasorEstimate {
  Phasor value;
  std::optional<double> se;
};

struct InfluenceCalibration {
  std::size_t sensors = 0, planes = 0, runs = 0;  ///< runs with known masses used
  std::size_t dof = 0;                            ///< runs - 1 - planes
  std::vector<PhasorEstimate> initial;            ///< a[s]
  std::vector<std::vector<PhasorEstimate>> h;     ///< h[s][p]
  std::vector<std::vector<Phasor>> residuals;     ///< per run used, per sensor
  /// The condition number of the influence matrix H (sensors x planes): large (say > 100) means
  /// the planes are not separable on these sensors.
  double condition = 0.0;
  /// Each sensor's reading noise variance s^2 (E|e|^2, complex), from the residuals; without
  /// degrees of freedom, the declared one (noise_declared) or empty.
  std::vector<double> noise_var;
  bool noise_declared = false;
  /// (X^H X)^-1 of the runs' design (1, masses), (planes + 1)^2 row-major: the covariance of a
  /// sensor's [a, h...] is noise_var[s] times it.
  std::vector<Phasor> design_inverse;
};

/// Fits the coefficients from the runs with known masses (check runs left out). Throws poise::Error when there are
/// fewer such runs than 1 + planes, or when their masses do not separate the planes (the
/// matrix of masses has lower rank).
/// declared_sd: the instrument's reading noise (the RMS size of a reading's error, E|e|^2 =
/// sd^2, in the readings' unit), used only where the runs leave no degrees of freedom: the
/// answers' regions then come from it alone (known variance), not from the campaign's scatter.
InfluenceCalibration calibrate(const std::vector<BalancingRun>& runs, std::size_t planes,
                               std::optional<double> declared_sd = std::nullopt);

/// The least-squares correction of the rotor as calibrated (its initial readings a), its
/// predicted residual readings, and their root mean square.
struct Correction {
  std::vector<Phasor> masses;    ///< per plane
  std::vector<Phasor> residual;  ///< per sensor
  double residual_rms = 0.0;
};
Correction correction(const InfluenceCalibration& c);

/// The masses that explain readings `v` beyond the initial ones: the unbalance of a run with
/// unknown masses, relative to the calibrated rotor (least squares over the sensors).
std::vector<Phasor> unbalance_of(const InfluenceCalibration& c, const std::vector<Phasor>& v);

}  // namespace poise::estimators
