#pragma once
/// Internal to residual_diagnosis.cc: the linear model with optional AR(1) errors that the
/// diagnosis refits for every candidate, and the tests of the candidates (statistics in
/// residual_diagnosis.h).
///
///     y = X beta + e,   e_t = rho e_{t-1} + u_t (t in measurement order),  u ~ N(0, s^2)
///
/// Prais-Winsten transform P: first point in measurement order scaled by sqrt(1 - rho^2),
/// every later one y_t - rho y_{t-1}; then ordinary least squares of P y on P X (GLS for the
/// given rho; OLS for rho = 0). Method: pivoted Householder QR of P X with its columns scaled
/// to unit norm, so the rank test does not depend on the columns' units (seconds, radians).
///
/// rho is found by maximum of the restricted (REML) profile log-likelihood
///     l_R(rho) = -(n - p)/2 ln S(rho) + 1/2 ln(1 - rho^2) - 1/2 ln det(X^T P^T P X)
/// (S = transformed RSS at the GLS beta), which is less biased than ML in short records; the
/// likelihood-ratio test of rho = 0 built on it holds its level at n = 36 (the ML one rejects
/// about twice as often as it should; measured over 20000 white-noise records).
#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace poise::estimators::detail {

/// |rho| bound of the AR(1) errors: stationary, with a finite ln(1 - rho^2).
inline constexpr double kMaxRho = 0.99;

/// The values and their measurement order.
struct ModelData {
  Eigen::VectorXd y;               ///< values, one per row
  std::vector<std::size_t> order;  ///< rows in measurement order
  double rss_floor = 0.0;          ///< keeps ln(RSS) finite for noise-free data
  Eigen::Index n = 0;
  double t_start = 0.0;  ///< time of the first measurement, from the mean time (K_T drift)
};

/// A least-squares fit, in the transformed (whitened) space when ar.
struct LinearFit {
  bool ok = false;        ///< false: rank-deficient design (columns not separable)
  Eigen::VectorXd beta;   ///< coefficients of the columns of X
  Eigen::MatrixXd cov;    ///< sigma^2 (X^T P^T P X)^-1, sigma^2 = RSS / dof
  Eigen::VectorXd resid;  ///< transformed residual P (y - X beta), indexed by row
  double rss = 0.0;       ///< transformed RSS
  double logdet = 0.0;    ///< ln det(X^T P^T P X)
  Eigen::Index dof = 0;   ///< n - p, one less with AR
};

/// Fits X (columns) with AR(1) errors of coefficient rho when ar, else by OLS.
LinearFit fit_linear(const Eigen::MatrixXd& x, const ModelData& d, bool ar, double rho);

/// l_R(rho) above (constants dropped); -infinity for a degenerate design.
double restricted_loglik(const Eigen::MatrixXd& x, const ModelData& d, double rho);

/// REML estimate of rho with its standard error (curvature of l_R) and l_R at it.
struct RhoFit {
  double rho = 0.0, se = 0.0, loglik = 0.0;
};

/// Grid over |rho| <= 0.99 (0 included), refined by golden section.
RhoFit fit_rho(const Eigen::MatrixXd& x, const ModelData& d);

/// A candidate effect: the columns it adds and, once tested, its statistics.
struct Term {
  Term(std::string name_, std::string label_, int order_ = 0, int index_ = -1)
      : name(std::move(name_)), order(order_), index(index_), label(std::move(label_)) {}
  std::string name;
  int order = 0, index = -1;  ///< harmonic order; outlier row
  Eigen::MatrixXd cols;       ///< columns it adds (none for autocorrelation)
  Eigen::Index first = 0;     ///< its first column once in the model
  double p = 1.0, p_adj = 1.0, delta_bic = 0.0;
  bool examined = false;    ///< false: not testable here (note says why)
  int round = 0;            ///< round in which it was added
  double param = 0.0;       ///< scanned parameter: exponential tau (time unit); else 0
  int scanned = 0;          ///< members of a scanned family (0: not a family)
  std::string label, note;  ///< for the list of candidates tested
};

/// The current model: columns (first three sin, cos, 1), the terms added, AR(1) errors.
struct Model {
  Eigen::MatrixXd x;
  std::vector<Term> terms;
  bool ar = false;
  RhoFit rho;
  bool has(const std::string& name, int order = 0) const {
    return std::any_of(terms.begin(), terms.end(), [&](const Term& t) { return t.name == name && t.order == order; });
  }
};

/// Residual degrees of freedom every model examined keeps.
inline constexpr Eigen::Index kMinResidualDof = 5;

/// [x add].
Eigen::MatrixXd with_columns(const Eigen::MatrixXd& x, const Eigen::MatrixXd& add);

/// Nested F test and delta_BIC of adding t.cols to m (with AR, both fitted at the rho of the
/// larger model, or at m's rho when !refit_rho: the fast form for scanning a family);
/// false, with t.note saying why, if not examinable.
bool nested_test(const Model& m, const ModelData& d, Term& t, bool refit_rho = true);

/// The outlier family: the point with the largest externally studentized residual, its p
/// Bonferroni-adjusted over the points examined.
Term outlier_family(const Model& m, const ModelData& d);

/// Restricted likelihood-ratio test of AR(1) errors given m's columns, one-sided (rho > 0).
Term autocorrelation_test(const Model& m, const ModelData& d);

/// Holm step-down adjustment of the examined terms' p (sets p_adj).
void holm(std::vector<Term>& c);

/// "label (note): p = ..., Holm-adjusted p = ..., delta_BIC = ..." for the report.
std::string describe(const Term& t);

}  // namespace poise::estimators::detail
