#include "sampling/cross_moments.h"

#include <cmath>

#include <Eigen/Dense>

namespace poise::sampling {

void CrossMoments::add(std::span<const double> inputs, std::span<const double> outputs) {
  const std::size_t m = inputs.size() + outputs.size();
  for (const auto* part : {&inputs, &outputs}) {
    for (double v : *part) {
      if (!std::isfinite(v)) return;  // a sample without every value is not counted
    }
  }
  if (n_ == 0) {
    p_ = inputs.size();
    q_ = outputs.size();
    shift_.assign(inputs.begin(), inputs.end());
    shift_.insert(shift_.end(), outputs.begin(), outputs.end());
    sum_.assign(m, 0.0);
    cross_.assign(m * m, 0.0);
  }
  if (inputs.size() != p_ || outputs.size() != q_) return;  // not the run's sizes: not counted
  double z[128];
  if (m > sizeof z / sizeof z[0]) return;
  for (std::size_t i = 0; i < p_; ++i) z[i] = inputs[i] - shift_[i];
  for (std::size_t k = 0; k < q_; ++k) z[p_ + k] = outputs[k] - shift_[p_ + k];
  for (std::size_t i = 0; i < m; ++i) {
    sum_[i] += z[i];
    for (std::size_t j = i; j < m; ++j) cross_[i * m + j] += z[i] * z[j];
  }
  ++n_;
}

std::optional<CrossMoments::Shares> CrossMoments::variance_shares(std::size_t output) const {
  if (n_ < p_ + 2 || output >= q_ || p_ == 0) return std::nullopt;
  const std::size_t m = p_ + q_;
  const double n = static_cast<double>(n_);
  const auto cov = [&](std::size_t i, std::size_t j) {
    if (i > j) std::swap(i, j);
    return (cross_[i * m + j] - sum_[i] * sum_[j] / n) / (n - 1.0);
  };
  const std::size_t y = p_ + output;
  const double var_y = cov(y, y);
  if (!(var_y > 0.0)) return std::nullopt;
  Eigen::MatrixXd cxx(p_, p_);
  Eigen::VectorXd cxy(p_);
  for (std::size_t i = 0; i < p_; ++i) {
    cxy(static_cast<Eigen::Index>(i)) = cov(i, y);
    for (std::size_t j = 0; j < p_; ++j) cxx(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = cov(i, j);
  }
  for (std::size_t i = 0; i < p_; ++i) {
    if (!(cxx(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) > 0.0)) return std::nullopt;
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(cxx);
  if (ldlt.info() != Eigen::Success) return std::nullopt;
  const Eigen::VectorXd b = ldlt.solve(cxy);
  Shares s;
  for (std::size_t i = 0; i < p_; ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    s.src2.push_back(b(ii) * b(ii) * cxx(ii, ii) / var_y);
  }
  s.r2 = b.dot(cxy) / var_y;
  return s;
}

}  // namespace poise::sampling
