#pragma once
/// Complex least squares for the balancing model's tests (estimators/balancing_model_tests.h):
/// a fit with its residual and rank, the extra-sum-of-squares F test between two nested fits,
/// and the figures the tests print. Internal to the estimators that test the balancing model.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Dense>
#include <boost/math/distributions/fisher_f.hpp>

#include "estimators/influence_coefficients.h"

namespace poise::estimators::complex_fit {

using CMatrix = Eigen::Matrix<Phasor, Eigen::Dynamic, Eigen::Dynamic>;
using CVector = Eigen::Matrix<Phasor, Eigen::Dynamic, 1>;

struct Fit {
  double rss = 0.0;
  Eigen::Index rank = 0;
  CVector beta;
};

inline Fit fit(const CMatrix& x, const CVector& y) {
  Eigen::ColPivHouseholderQR<CMatrix> qr(x);
  qr.setThreshold(1e-10);
  Fit f;
  f.rank = qr.rank();
  f.beta = qr.solve(y);
  f.rss = (y - x * f.beta).squaredNorm();
  return f;
}

// A phasor's angle in degrees, 0 to 360.
inline double degrees_of(const Phasor& z) { return std::fmod(std::arg(z) * 180.0 / std::numbers::pi + 360.0, 360.0); }

// The extra-sum-of-squares F test of fit f1 (q more complex terms, nu complex residual degrees of
// freedom) over f0: each complex term and residual counts twice.
inline double extra_sum_of_squares_p(const Fit& f0, const Fit& f1, Eigen::Index q, Eigen::Index nu) {
  const double f = ((f0.rss - f1.rss) / (2.0 * static_cast<double>(q))) / (f1.rss / (2.0 * static_cast<double>(nu)));
  return boost::math::cdf(boost::math::complement(
      boost::math::fisher_f(2.0 * static_cast<double>(q), 2.0 * static_cast<double>(nu)), std::max(f, 0.0)));
}

// The root mean square of `count` complex residuals whose squared sizes sum to rss.
inline double rms(double rss, Eigen::Index count) {
  return std::sqrt(rss / static_cast<double>(std::max<Eigen::Index>(count, 1)));
}

}  // namespace poise::estimators::complex_fit
