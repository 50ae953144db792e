#pragma once
/// Omnibus check of the residual of a final model: is there structure in it that no selected
/// effect explains? Run after the stepwise selection of residual_diagnosis.h; it never adds an
/// effect, it says whether the estimate carries something unexplained, and where.
///
/// Tests (each examined only where the data allow it; r = residual, p = fitted columns):
///   lack_of_fit   repeated positions (the same angle modulo 360 deg measured more than once):
///                 pure error SS_pe = sum_g sum_i (r_i - mean_g r)^2 on n - G dof, lack of fit
///                 SS_lof = RSS - SS_pe on G - p dof; F = (SS_lof/(G-p)) / (SS_pe/(n-G)),
///                 upper tail of F(G - p, n - G). Needs G > p and n > G.
///   declared_noise  with an independent noise level sigma0 (`--noise`, e.g. the scatter of
///                 the period integrals within a position divided by sqrt(periods)):
///                 RSS / sigma0^2 ~ chi^2(n - p); upper tail (more scatter than the noise).
///                 With a standard error per point (torque_se_* column): sum (r_i / s_i)^2.
///   ljung_box     Q = n (n + 2) sum_{k=1..h} rho_k^2 / (n - k) of r in measurement order,
///                 h = round(ln n) (at least 2; Tsay 2010); chi^2(h) (h - 1 with AR(1) errors in the model,
///                 whose innovations are tested). Needs n >= 12.
///   runs          Wald-Wolfowitz runs of the signs of r in measurement order, normal
///                 approximation, two-sided: too few runs is slow structure (a drift, a step,
///                 correlated noise), too many an alternating one (a direction offset).
///   cusum_step    max_k |sum_{i<=k} r_(i)| / (s sqrt(n)), s^2 = RSS / (n - p), measurement
///                 order; under no shift it tends to the sup of a Brownian bridge, tail
///                 P = 2 sum_j (-1)^(j-1) exp(-2 j^2 x^2) (Kolmogorov; the OLS-CUSUM test of
///                 Ploberger and Kraemer 1992). The argmax is where a level shift sits.
///   periodogram   the periodogram's largest ordinate of r in measurement order, on a grid 8
///                 times finer than the Fourier frequencies (residual_periodogram.h): a periodic
///                 effect in time that no candidate names (a thermostat's cycle, a sawtooth) and
///                 a harmonic of the turntable angle above the candidates' orders on a
///                 one-direction sweep. Always a Monte Carlo p (no closed-form tail). n >= 12.
/// Residuals of a regression are not white even when the errors are: on a sweep the fitted
/// sin, cos and drift columns are smooth in time and bias the residual autocorrelations, and
/// the asymptotic Ljung-Box tail rejected 3.6 times too often (measured on the independent
/// generator's clean forward-and-back tables). With the design given, the four
/// order-based tests take Monte Carlo p-values instead: 400 draws r = (I - H) z, z ~ N(0, I),
/// H the hat matrix of the design, fixed seed; p = (1 + #{T_sim >= T}) / 401, exact under
/// Gaussian errors whatever the design.
/// The family's p is Bonferroni over the tests examined (min p times their number), so a
/// record with independent noise and a correct model is flagged in at most about alpha of
/// cases. Measured on tests/independent_gimbal_data: see residual_omnibus_test.cc.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace poise::estimators {

/// One test of the omnibus family.
struct StructureTest {
  std::string name;        ///< lack_of_fit, declared_noise, ljung_box, runs, cusum_step, periodogram
  bool examined = false;   ///< false: the data do not allow it (note says why)
  double statistic = 0.0;  ///< F, chi^2, Q, z or the CUSUM sup
  double p_value = 1.0;
  std::string note;
};

/// The residual of the final model, with what locates each point.
struct OmnibusInput {
  std::vector<double> residual;         ///< per row (with AR(1): the innovations)
  std::vector<std::size_t> order;       ///< rows in measurement order
  std::vector<double> theta_deg;        ///< per row
  std::vector<double> time_s;           ///< per row; empty: none
  std::vector<std::size_t> lines;       ///< per row, 1-based file line; empty: none
  std::size_t parameters = 3;           ///< fitted columns p (AR not counted)
  bool ar = false;                      ///< residual are AR(1) innovations
  double noise = 0.0;                   ///< declared independent noise sd; 0 = none
  std::vector<double> noise_per_point;  ///< per row (e.g. from period scatter); wins over noise
  double alpha = 0.05;
  /// The final model's columns (rows as residual); when given (and !ar) the Ljung-Box, runs,
  /// CUSUM and periodogram p-values are Monte Carlo ones under this design (see above).
  Eigen::MatrixXd design;
};

/// Result: every test, the family p, and where the structure sits when it is flagged.
struct OmnibusResult {
  std::vector<StructureTest> tests;
  double p_value = 1.0;      ///< Bonferroni over the examined tests
  bool unexplained = false;  ///< p_value < alpha
  std::string where;         ///< rows, angles, times of the structure (when flagged)
  std::string message;       ///< one sentence, flagged or not: never silent
};

/// The Monte Carlo draws of the residual above, in measurement order: r = (I - H) z under
/// in.design (`projected`), or the white z itself (then in row order), z ~ N(0, I) from a
/// fixed seed. One source for every Monte Carlo p of the family.
class ResidualDraws {
 public:
  ResidualDraws(const OmnibusInput& in, bool projected, std::uint64_t seed);
  /// The next draw into `ordered` (size n).
  void next(std::vector<double>& ordered);
  /// Rank of the design (0 when not projected).
  Eigen::Index rank() const { return rank_; }

 private:
  const std::vector<std::size_t>& order_;
  bool projected_;
  Eigen::MatrixXd q_;  ///< orthonormal basis of the design's columns
  Eigen::Index rank_ = 0;
  Eigen::VectorXd z_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_;
};

/// Runs the family on in.residual. Deterministic; never throws for n >= 4.
OmnibusResult omnibus_check(const OmnibusInput& in);

/// Upper tail of the sup of a Brownian bridge, P(sup |B| > x) (Kolmogorov distribution).
double brownian_bridge_sup_tail(double x);

}  // namespace poise::estimators
