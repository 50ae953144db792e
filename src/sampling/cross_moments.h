#pragma once
/// The means and covariances of a run's inputs and outputs, accumulated one sample at a time
/// (no sample kept), for the share of each output's variance each input explains: the squared
/// standardized regression coefficients (SRC^2) of the output on the inputs,
///   b = Cov(x, x)^-1 Cov(x, y),  SRC_i = b_i sd(x_i) / sd(y),
/// which for independent inputs and an output linear in them are each input's share of the
/// output's variance (they sum to R^2, 1 for a linear output); for a nonlinear one they are the
/// first-order shares of its linear part (Saltelli et al. 2008, Global Sensitivity Analysis,
/// sec. 1.2.5). Sums are taken about the first sample's values, so that inputs with a large mean
/// and a small spread (a 60 mm housing +-0.05 mm) lose no digits.
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

namespace poise::sampling {

class CrossMoments {
 public:
  /// Adds one sample's inputs and outputs (every sample the same sizes; one with a value that
  /// is not finite is left out).
  void add(std::span<const double> inputs, std::span<const double> outputs);
  std::size_t count() const { return n_; }
  std::size_t inputs() const { return p_; }
  /// SRC^2 of each input for output k, and R^2 (their sum for independent inputs); nullopt
  /// when there are fewer samples than inputs + 2, or an input or the output does not vary.
  struct Shares {
    std::vector<double> src2;
    double r2 = 0.0;
  };
  std::optional<Shares> variance_shares(std::size_t output) const;

 private:
  std::size_t n_ = 0, p_ = 0, q_ = 0;
  std::vector<double> shift_, sum_, cross_;  // shift and sums of z = (x, y) - shift; cross: z z^T
};

}  // namespace poise::sampling
