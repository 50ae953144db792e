#include "sampling/statistics.h"

#include <algorithm>
#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>

#include "core/error.h"

namespace poise::sampling {

Estimate quantile_sorted(std::span<const double> sorted, double p) {
  const std::size_t n = sorted.size();
  require(n > 0, "quantile of an empty sample");
  Estimate e;
  const double h = (static_cast<double>(n) - 1.0) * p;
  const auto lo_i = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi_i = std::min(lo_i + 1, n - 1);
  e.value = sorted[lo_i] + (h - static_cast<double>(lo_i)) * (sorted[hi_i] - sorted[lo_i]);
  // Order statistics X(l) <= q_p <= X(u) (1-based) with P >= 95%: l is the smallest l with
  // P(B <= l - 1) <= 0.025 taken from the top, u = binomial quantile(0.975) + 1.
  // Boost's quantile(bin, 0.025) is the largest x with cdf(x) <= 0.025, i.e. l - 1.
  boost::math::binomial_distribution<double> bin(static_cast<double>(n), p);
  const double q = std::floor(boost::math::quantile(bin, 0.025));
  const double l = boost::math::cdf(bin, q) <= 0.025 ? q + 1.0 : 0.0;
  const double u = std::ceil(boost::math::quantile(bin, 0.975)) + 1.0;
  if (l >= 1.0) e.lo = sorted[static_cast<std::size_t>(l) - 1];
  if (u <= static_cast<double>(n)) e.hi = sorted[static_cast<std::size_t>(u) - 1];
  return e;
}

Estimate fraction_wilson(std::size_t successes, std::size_t n) {
  require(n > 0, "fraction of an empty sample");
  const double z = 1.959963984540054;
  const double nn = static_cast<double>(n);
  const double ph = static_cast<double>(successes) / nn;
  const double denom = 1.0 + z * z / nn;
  const double centre = (ph + z * z / (2.0 * nn)) / denom;
  const double half = z * std::sqrt(ph * (1.0 - ph) / nn + z * z / (4.0 * nn * nn)) / denom;
  // The Wilson ends are exactly 0 and 1 at 0 and n successes (rounding would miss them).
  const double lo = successes == 0 ? 0.0 : std::max(0.0, centre - half);
  const double hi = successes == n ? 1.0 : std::min(1.0, centre + half);
  return {ph, lo, hi};
}

Summary summarize(std::span<const double> values) {
  const std::size_t n = values.size();
  require(n > 0, "summary of an empty sample");
  std::vector<double> sorted(values.begin(), values.end());
  std::sort(sorted.begin(), sorted.end());
  Summary s;
  s.n = n;
  const double nn = static_cast<double>(n);
  double mean = 0.0;
  for (double v : sorted) mean += v;
  mean /= nn;
  double m2 = 0.0, m4 = 0.0;
  for (double v : sorted) {
    const double d = (v - mean) * (v - mean);
    m2 += d;
    m4 += d * d;
  }
  const double var = n > 1 ? m2 / (nn - 1.0) : 0.0;
  m4 /= nn;
  const double sd = std::sqrt(var);
  s.mean.value = mean;
  if (n > 1) {
    boost::math::students_t t(nn - 1.0);
    const double half = boost::math::quantile(t, 0.975) * sd / std::sqrt(nn);
    s.mean.lo = mean - half;
    s.mean.hi = mean + half;
  }
  s.std.value = sd;
  if (n > 3 && sd > 0.0) {
    const double var_s2 = std::max(0.0, (m4 - var * var * (nn - 3.0) / (nn - 1.0)) / nn);
    const double se_s = std::sqrt(var_s2) / (2.0 * sd);  // delta method: d sqrt(x) = dx / (2 sqrt x)
    s.std.lo = std::max(0.0, sd - 1.959963984540054 * se_s);
    s.std.hi = sd + 1.959963984540054 * se_s;
  }
  s.p50 = quantile_sorted(sorted, 0.50);
  s.p95 = quantile_sorted(sorted, 0.95);
  s.p99_73 = quantile_sorted(sorted, 0.9973);
  s.max.value = sorted.back();
  s.max.lo = quantile_sorted(sorted, nn / (nn + 1.0)).lo;
  return s;
}

}  // namespace poise::sampling
