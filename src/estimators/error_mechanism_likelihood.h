#pragma once
/// Which per-test error makes a static-unbalance test's result differ from the load it was
/// given? Likelihood of the candidate mechanisms on measured tests (Yang et al. 2015, Tables
/// 2-5: a load of known torque L and angle a, measured as MT_s and b by a whole 18- or
/// 36-point test).
///
/// Each test's error as a vector in the load's frame (exact, a rotation of U_meas - U_load):
///     r = MT_s cos(b - a) - L   (along the load: the torque error, to first order)
///     t = MT_s sin(b - a)       (across it: L times the angle error)
/// Candidates, every error drawn anew for each test, independent between tests:
///   scale_and_zero  U_meas = (1 + k) R(z) U_load + e, k ~ N(0, s_k) (K_T between tests),
///                   z ~ N(0, s_z) (gimbal zero): r = L k, t = L z to first order (the
///                   neglected L z^2 / 2 is 0.002 mN*m at the calibrated 0.83 deg, 12.9 mN*m);
///   additive        U_meas = U_load + d + e, d ~ N(0, s_d^2 I) (any direction): r, t = d;
///   additive_along_across  d with s_along along the unbalance and s_across across it;
///   scale_zero_and_additive  both at once (nests the first two: likelihood-ratio tests).
/// e is the fit's own noise: with per-position noise sigma_p and n evenly spaced positions
/// the sin and cos coefficients of Eq. 22 each have variance 2 sigma_p^2 / n (sine_fit.h).
/// So every candidate gives independent normal r and t with
///     var_r = L^2 s_k^2 + s_along^2 + 2 sigma_p^2 / n,  var_t = L^2 s_z^2 + s_across^2 + 2 sigma_p^2 / n
/// and the log-likelihood is the sum over tests of the two normal log-densities (the printed
/// figures' rounding, 0.01 mN*m and 0.01 deg, adds 1e-5 mN*m^2 and is left out).
/// Maximum likelihood: the variances are components, fitted by cyclic one-dimensional Brent
/// searches (Boost.Math) over each free sigma in [0, 10 x the largest |r|, |t|].
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace poise::estimators {

/// One measured test: the load it was given and what it measured (SI: N*m, rad).
struct UnbalanceTestRecord {
  std::string table;         ///< e.g. "Table 2"
  int number = 0;            ///< test number in its table
  double load_torque = 0.0;  ///< L (N*m)
  double load_angle = 0.0;   ///< a (rad)
  double torque = 0.0;       ///< MT_s measured (N*m)
  double angle = 0.0;        ///< b measured (rad)
  int positions = 36;        ///< turntable positions of the test
};

enum class ErrorMechanism { kScaleAndZero, kAdditive, kAdditiveAlongAcross, kScaleZeroAndAdditive };
const char* to_string(ErrorMechanism m);  ///< "scale_and_zero", "additive", ...
int parameter_count(ErrorMechanism m);    ///< free sigmas: 2, 1, 2, 3

/// The candidates' standard deviations (1 sigma). Unused ones stay 0.
struct MechanismSigmas {
  double scale = 0.0;   ///< s_k, relative
  double zero = 0.0;    ///< s_z (rad)
  double along = 0.0;   ///< additive error along the unbalance (N*m); s_d for `additive`
  double across = 0.0;  ///< additive error across it (N*m); s_d for `additive`
};

/// (r, t) of one test, N*m.
struct LoadFrameError {
  double along = 0.0;
  double across = 0.0;
};
LoadFrameError load_frame_error(const UnbalanceTestRecord& t);

/// Per-component variance of the fit's own noise, 2 sigma_p^2 / n (N*m^2).
inline double fit_noise_variance(double position_noise, int positions) {
  return 2.0 * position_noise * position_noise / positions;
}

/// Sum over `tests` of the log-density of (r, t) under `s` (natural log; (r, t) in N*m).
double mechanism_log_likelihood(std::span<const UnbalanceTestRecord> tests, const MechanismSigmas& s,
                                double position_noise);

/// Maximum-likelihood sigmas of mechanism `m` on `tests`.
MechanismSigmas fit_mechanism(std::span<const UnbalanceTestRecord> tests, ErrorMechanism m, double position_noise);

/// Spearman rank correlation (average ranks for ties).
double spearman(std::span<const double> x, std::span<const double> y);
/// Pearson correlation.
double pearson(std::span<const double> x, std::span<const double> y);

/// Posterior-predictive check of `tests` under `s`: the share of `draws` simulated copies
/// (the same loads, errors drawn from the model, exact transformation to MT_s and b) whose
/// statistic is at or beyond the measured one. Statistics: Spearman of |dMT| and of |db|
/// against the load (share at or below the measured value: falling with the load), and
/// Pearson of dMT with db (share with |rho| at or above the measured |rho|).
struct PredictiveCheck {
  double spearman_torque = 0.0, spearman_angle = 0.0, pearson_torque_angle = 0.0;  ///< measured
  double p_spearman_torque = 0.0, p_spearman_angle = 0.0, p_pearson = 0.0;         ///< shares
};
PredictiveCheck predictive_check(std::span<const UnbalanceTestRecord> tests, const MechanismSigmas& s,
                                 double position_noise, int draws, std::uint64_t seed);

}  // namespace poise::estimators
