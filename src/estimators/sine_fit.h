#pragma once
/// Least-squares sine fit of a once-per-turn signal, e.g. the static unbalance torque.
///
/// Model (Yang, Zhao, Li, Wu 2015, Sec. 5.2, Eq. 22): the static unbalance torque measured with
/// the turntable locked at angle theta_i is
///
///     M(theta) = MT_s sin(theta + b) + MK
///
/// with MT_s the unbalance torque (amplitude), b its phase and MK a constant disturbance torque.
/// It is non-linear in (MT_s, b) but linear in (a, c, K) with a = MT_s cos b, c = MT_s sin b:
///
///     M(theta) = a sin(theta) + c cos(theta) + K,
///
/// so the fit is an ordinary linear least-squares problem; amplitude = hypot(a, c) >= 0 and
/// phase = atan2(c, a) wrapped to [0, 2 pi), so a negative amplitude never occurs. The fitted
/// MT_s and b are what Eq. 23 consumes: counterweight m = MT_s / (R g), placed opposite the
/// unbalance.
///
/// Check against the paper: the fit of Table 1 (36 points) is 12.475 sin(theta + 42.43 deg)
/// + 3.428 mN*m with largest residual 0.636 mN*m. The paper prints 12.04, 44.20 deg and 3.47
/// (Eq. 24) but 0.64 mN*m for the largest residual. Its amplitude is 7.8 and its phase 7.0
/// standard errors from the least-squares ones (offset 1.1), and its curve leaves a largest
/// residual of 0.93 mN*m: Eq. 24 is not the least-squares fit of the printed table (the same
/// table in both OCRs of the paper; dropping any one point moves the fit by < 0.05 mN*m and
/// < 0.1 deg). The fit was confirmed by an independent normal-equation solution
/// (tests/estimators/sine_fit_test.cc).
///
/// Method: Householder QR with column pivoting (Eigen::ColPivHouseholderQR) of the n x 3 design
/// matrix X = [sin theta, cos theta, 1]. Why not the normal equations: X^T X squares the
/// condition number of X, harmless for angles all round the turn (X^T X = diag(n/2, n/2, n))
/// but costly when the angles cover a short arc, where sin, cos and 1 become nearly collinear;
/// QR keeps the accuracy of X and its pivoted R gives the rank test for a degenerate design.
///
/// Uncertainty (independent residuals of equal variance, the usual least-squares assumptions):
///
///     SSR   = sum_i r_i^2,   r_i = value_i - (a sin theta_i + c cos theta_i + K)
///     rmse  = sqrt(SSR / n)                    (RMS of the residuals)
///     sigma = sqrt(SSR / (n - 3))              (unbiased residual standard deviation)
///     Cov(a, c, K) = sigma^2 (X^T X)^-1 = sigma^2 P R^-1 R^-T P^T    (X P = Q R)
///
/// Delta method, with A = amplitude, phi = phase:
///
///     dA/da = a/A,      dA/dc = c/A
///     dphi/da = -c/A^2, dphi/dc = a/A^2
///     se_amplitude^2 = (a^2 C_aa + 2 a c C_ac + c^2 C_cc) / A^2
///     se_phase^2     = (c^2 C_aa - 2 a c C_ac + a^2 C_cc) / A^4      (rad^2)
///     se_offset^2    = C_KK
///
/// The delta method is a first-order approximation: it is good while A is many standard errors
/// from zero (se_phase well below about 0.3 rad). For A == 0 exactly the phase is undefined:
/// se_phase is then +infinity and se_amplitude is sqrt((C_aa + C_cc) / 2).
#include <Eigen/Core>
#include <cstddef>
#include <span>
#include <vector>

namespace poise::estimators {

/// Result of fit_sine. Values are in the unit of the fitted values; angles in radians.
struct SineFitResult {
  std::size_t n = 0;                                     ///< number of points
  double amplitude = 0.0;                                ///< MT_s = hypot(a, c) >= 0
  double phase = 0.0;                                    ///< b = atan2(c, a), rad, wrapped to [0, 2 pi)
  double offset = 0.0;                                   ///< MK = K
  double se_amplitude = 0.0;                             ///< standard error of amplitude (delta method)
  double se_phase = 0.0;                                 ///< standard error of phase, rad (delta method)
  double se_offset = 0.0;                                ///< standard error of offset
  double rmse = 0.0;                                     ///< sqrt(SSR / n): RMS of the residuals
  double sigma = 0.0;                                    ///< sqrt(SSR / (n - 3)): residual standard deviation
  double max_abs_residual = 0.0;                         ///< max_i |r_i|
  std::vector<double> residuals;                         ///< r_i = value_i - fitted_i, in input order
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  ///< of (a, c, K)
};

/// Fits value_i = amplitude sin(theta_i + phase) + offset by linear least squares (see above).
/// theta_rad: angles in radians (any range; only their values modulo 2 pi matter).
/// Throws poise::Error when n < 4 (sigma needs n - 3 > 0), the sizes differ, a value or angle
/// is not finite, fewer than 3 angles are distinct modulo 2 pi, or the design is numerically
/// rank-deficient.
SineFitResult fit_sine(std::span<const double> theta_rad, std::span<const double> value);

/// Number of distinct positions among the angles, modulo 2 pi: angles closer than 1e-9 rad
/// (0 and 2 pi included) count as one. fit_sine needs at least 3.
std::size_t count_distinct_angles(std::span<const double> theta_rad);

/// The fitted model at theta_rad: amplitude sin(theta + phase) + offset.
double sine_fit_predict(const SineFitResult& fit, double theta_rad);

}  // namespace poise::estimators
