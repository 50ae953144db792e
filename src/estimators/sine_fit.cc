#include "estimators/sine_fit.h"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/angles.h"
#include "core/error.h"

namespace poise::estimators {
namespace {

using angles::kTwoPi;
// Angles closer than this (rad, about 0.2 milli-arcsec) count as the same position.
constexpr double kSameAngle = 1e-9;
// |R_ii| below this fraction of the largest pivot: rank-deficient (the design cannot tell
// sin, cos and the offset apart to any useful accuracy).
constexpr double kRankThreshold = 1e-10;

using angles::wrap_two_pi;

void check_input(std::span<const double> theta_rad, std::span<const double> value) {
  if (theta_rad.size() != value.size()) {
    throw Error("fit_sine: " + std::to_string(theta_rad.size()) + " angles but " + std::to_string(value.size()) +
                " values; expected one value per angle");
  }
  if (theta_rad.size() < 4) {
    throw Error("fit_sine: " + std::to_string(theta_rad.size()) +
                " points; expected at least 4 (3 parameters plus 1 for the residual spread)");
  }
  for (std::size_t i = 0; i < theta_rad.size(); ++i) {
    if (!std::isfinite(theta_rad[i]) || !std::isfinite(value[i])) {
      throw Error("fit_sine: point " + std::to_string(i) + " (theta = " + std::to_string(theta_rad[i]) +
                  " rad, value = " + std::to_string(value[i]) + ") is not finite");
    }
  }
  const std::size_t distinct = count_distinct_angles(theta_rad);
  if (distinct < 3) {
    throw Error("fit_sine: only " + std::to_string(distinct) +
                " distinct angle(s) modulo 360 deg; expected at least 3 to determine amplitude, "
                "phase and offset");
  }
}

}  // namespace

std::size_t count_distinct_angles(std::span<const double> theta_rad) {
  if (theta_rad.empty()) return 0;
  std::vector<double> w(theta_rad.size());
  std::transform(theta_rad.begin(), theta_rad.end(), w.begin(), wrap_two_pi);
  std::sort(w.begin(), w.end());
  std::size_t distinct = 1;
  for (std::size_t i = 1; i < w.size(); ++i) {
    if (w[i] - w[i - 1] > kSameAngle) ++distinct;
  }
  // 0 and 2 pi - epsilon are the same position.
  if (distinct > 1 && w.front() + kTwoPi - w.back() <= kSameAngle) --distinct;
  return distinct;
}

SineFitResult fit_sine(std::span<const double> theta_rad, std::span<const double> value) {
  check_input(theta_rad, value);
  const auto n = static_cast<Eigen::Index>(theta_rad.size());
  Eigen::MatrixX3d x(n, 3);
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    x(i, 0) = std::sin(theta_rad[k]);
    x(i, 1) = std::cos(theta_rad[k]);
    x(i, 2) = 1.0;
    y(i) = value[k];
  }

  Eigen::ColPivHouseholderQR<Eigen::MatrixX3d> qr(x);
  qr.setThreshold(kRankThreshold);
  if (qr.rank() < 3) {
    throw Error("fit_sine: the design [sin theta, cos theta, 1] is rank-deficient (rank " + std::to_string(qr.rank()) +
                " of 3): the angles are too close together to separate amplitude, phase and "
                "offset; spread them over the turn");
  }
  const Eigen::Vector3d beta = qr.solve(y);
  const Eigen::VectorXd r = y - x * beta;

  SineFitResult fit;
  fit.n = theta_rad.size();
  const double a = beta(0), c = beta(1);
  fit.amplitude = std::hypot(a, c);
  fit.phase = wrap_two_pi(std::atan2(c, a));
  fit.offset = beta(2);
  fit.residuals.assign(r.data(), r.data() + n);
  const double ssr = r.squaredNorm();
  fit.rmse = std::sqrt(ssr / static_cast<double>(n));
  fit.sigma = std::sqrt(ssr / static_cast<double>(n - 3));
  fit.max_abs_residual = r.cwiseAbs().maxCoeff();

  // (X^T X)^-1 = P R^-1 R^-T P^T = L L^T from X P = Q R; X^T X itself is never formed.
  const Eigen::Matrix3d rr = qr.matrixR().topLeftCorner<3, 3>().triangularView<Eigen::Upper>();
  const Eigen::Matrix3d r_inv = rr.triangularView<Eigen::Upper>().solve(Eigen::Matrix3d::Identity());
  const Eigen::Matrix3d l = qr.colsPermutation() * r_inv;
  fit.covariance = fit.sigma * fit.sigma * (l * l.transpose());

  // se of g^T beta is sigma |L^T g|: a norm, so never negative through rounding.
  const auto se_of = [&](const Eigen::Vector3d& g) { return fit.sigma * (l.transpose() * g).norm(); };
  const double amp = fit.amplitude;
  if (amp > 0.0) {
    // Unit gradients (a, c) / A and (-c, a) / A keep the products in range for any A.
    const double ua = a / amp, uc = c / amp;
    fit.se_amplitude = se_of(Eigen::Vector3d(ua, uc, 0.0));
    fit.se_phase = se_of(Eigen::Vector3d(-uc, ua, 0.0)) / amp;
  } else {
    fit.se_amplitude = std::sqrt(0.5 * (fit.covariance(0, 0) + fit.covariance(1, 1)));
    fit.se_phase = std::numeric_limits<double>::infinity();
  }
  fit.se_offset = se_of(Eigen::Vector3d(0.0, 0.0, 1.0));
  return fit;
}

double sine_fit_predict(const SineFitResult& fit, double theta_rad) {
  return fit.amplitude * std::sin(theta_rad + fit.phase) + fit.offset;
}

}  // namespace poise::estimators
