#include "sampling/statistics.h"

#include <algorithm>
#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <boost/math/special_functions/beta.hpp>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/format.h"

namespace poise::sampling {

namespace {

// 0-based ranks a quantile needs: the interpolation pair and, optionally, its CI ends.
struct QuantileRanks {
  std::size_t lo_i = 0, hi_i = 0;
  double frac = 0.0;
  std::optional<std::size_t> ci_lo, ci_hi;
};

QuantileRanks quantile_ranks(std::size_t n, double p, bool with_ci) {
  QuantileRanks r;
  // Definition 8 (Hyndman & Fan 1996): 1-based rank (n + 1/3) p + 1/3, clamped to [1, n].
  const double nn = static_cast<double>(n);
  const double h = std::clamp((nn + 1.0 / 3.0) * p + 1.0 / 3.0, 1.0, nn) - 1.0;  // 0-based
  r.lo_i = std::min(static_cast<std::size_t>(std::floor(h)), n - 1);
  r.hi_i = std::min(r.lo_i + 1, n - 1);
  r.frac = h - static_cast<double>(r.lo_i);
  if (!with_ci) return r;
  // Order statistics X(l) <= q_p <= X(u) (1-based) with P >= 95%: l is the smallest l with
  // P(B <= l - 1) <= 0.025 taken from the top, u = binomial quantile(0.975) + 1.
  // Boost's quantile(bin, 0.025) is the largest x with cdf(x) <= 0.025, i.e. l - 1.
  boost::math::binomial_distribution<double> bin(static_cast<double>(n), p);
  const double q = std::floor(boost::math::quantile(bin, 0.025));
  const double l = boost::math::cdf(bin, q) <= 0.025 ? q + 1.0 : 0.0;
  const double u = std::ceil(boost::math::quantile(bin, 0.975)) + 1.0;
  if (l >= 1.0) r.ci_lo = static_cast<std::size_t>(l) - 1;
  if (u <= static_cast<double>(n)) r.ci_hi = static_cast<std::size_t>(u) - 1;
  return r;
}

// at(k) = k-th smallest value (0-based).
template <class At>
Estimate quantile_at(const QuantileRanks& r, At at) {
  Estimate e;
  e.value = at(r.lo_i) + r.frac * (at(r.hi_i) - at(r.lo_i));
  if (r.ci_lo) e.lo = at(*r.ci_lo);
  if (r.ci_hi) e.hi = at(*r.ci_hi);
  return e;
}

// The note of a quantile's order-statistic interval with an end missing.
void note_missing_ends(Estimate& e, std::size_t n, double p) {
  if (e.lo && e.hi) return;
  if (!e.lo && !e.hi) {
    e.note = "no interval: " + std::to_string(n) + " samples are too few for either end";
  } else if (!e.hi) {
    e.note = "one-sided: no upper bound below n = " + std::to_string(samples_for_upper_end(p)) +
             " (the upper 97.5% order statistic of p" + fixed(100.0 * p, 0) + " lies past the largest of " +
             std::to_string(n) + " samples)";
  } else {
    e.note = "one-sided: no lower bound below n = " + std::to_string(samples_for_upper_end(1.0 - p));
  }
}

constexpr SummaryQuantile kSummaryQuantiles[] = {
    {"p0_135", 0.00135, &Summary::p0_135},  {"p2_5", 0.025, &Summary::p2_5},   {"p50", 0.50, &Summary::p50},
    {"p95", 0.95, &Summary::p95},           {"p97_5", 0.975, &Summary::p97_5}, {"p99_73", 0.9973, &Summary::p99_73},
    {"p99_865", 0.99865, &Summary::p99_865}};

}  // namespace

std::span<const SummaryQuantile> summary_quantiles() { return kSummaryQuantiles; }

std::size_t samples_for_upper_end(double p) {
  // The upper end X(u) exists when P(Binomial(n, p) <= n - 1) = 1 - p^n >= 0.975.
  if (!(p > 0.0)) return 1;
  if (!(p < 1.0)) return static_cast<std::size_t>(-1);
  return static_cast<std::size_t>(std::ceil(std::log(0.025) / std::log(p) - 1e-9));
}

Estimate quantile_sorted(std::span<const double> sorted, double p) {
  POISE_INVARIANT(!sorted.empty(), "quantile of an empty sample");
  Estimate e = quantile_at(quantile_ranks(sorted.size(), p, true), [&](std::size_t k) { return sorted[k]; });
  note_missing_ends(e, sorted.size(), p);
  return e;
}

double quantile_value(std::span<double> data, double p) {
  POISE_INVARIANT(!data.empty(), "quantile of an empty sample");
  const QuantileRanks r = quantile_ranks(data.size(), p, false);
  std::nth_element(data.begin(), data.begin() + static_cast<long>(r.lo_i), data.end());
  const double lo = data[r.lo_i];
  const double hi = r.hi_i == r.lo_i ? lo : *std::min_element(data.begin() + static_cast<long>(r.hi_i), data.end());
  return lo + r.frac * (hi - lo);
}

double quantile_value_sorted(std::size_t n, double p, const std::function<double(std::size_t)>& sorted_at) {
  POISE_INVARIANT(n > 0, "quantile of an empty sample");
  const QuantileRanks r = quantile_ranks(n, p, false);
  const double lo = sorted_at(r.lo_i);
  const double hi = sorted_at(r.hi_i);
  return lo + r.frac * (hi - lo);
}

Estimate fraction_wilson(std::size_t successes, std::size_t n) {
  POISE_INVARIANT(n > 0, "fraction of an empty sample");
  const double z = 1.959963984540054;
  const double nn = static_cast<double>(n);
  const double ph = static_cast<double>(successes) / nn;
  const double denom = 1.0 + z * z / nn;
  const double centre = (ph + z * z / (2.0 * nn)) / denom;
  const double half = z * std::sqrt(ph * (1.0 - ph) / nn + z * z / (4.0 * nn * nn)) / denom;
  // The Wilson ends are exactly 0 and 1 at 0 and n successes (rounding would miss them).
  const double lo = successes == 0 ? 0.0 : std::max(0.0, centre - half);
  const double hi = successes == n ? 1.0 : std::min(1.0, centre + half);
  return {ph, lo, hi, {}};
}

Summary summarize(std::span<const double> values) {
  const std::size_t n = values.size();
  POISE_INVARIANT(n > 0, "summary of an empty sample");
  std::vector<double> data(values.begin(), values.end());
  SummaryMoments m;
  m.n = n;
  for (double v : data) m.mean += v;
  m.mean /= static_cast<double>(n);
  for (double v : data) {
    const double d = (v - m.mean) * (v - m.mean);
    m.m2 += d;
    m.m4 += d * d;
  }
  // Only a dozen order statistics are needed: select them in increasing rank with
  // nth_element on what is left, instead of sorting everything.
  std::size_t start = 0;
  for (std::size_t k : summary_ranks(n)) {
    std::nth_element(data.begin() + static_cast<long>(start), data.begin() + static_cast<long>(k), data.end());
    start = k + 1;
  }
  // After the loop data[k] is the k-th smallest for every selected k.
  Summary s = summarize_from(m, [&](std::size_t k) { return data[k]; });
  // A share (every value 0 or 1: a pass ratio, a yield) gets the exact binomial interval of its
  // mean: the t interval of 64 passes in 64 is [1, 1], the data's is [0.944, 1].
  if (std::all_of(values.begin(), values.end(), [](double v) { return v == 0.0 || v == 1.0; })) {
    const double k = std::round(m.mean * static_cast<double>(n)), nn = static_cast<double>(n);
    s.mean.lo = k <= 0.0 ? 0.0 : boost::math::ibeta_inv(k, nn - k + 1.0, 0.025);
    s.mean.hi = k >= nn ? 1.0 : boost::math::ibeta_inv(k + 1.0, nn - k, 0.975);
    s.mean.note = "exact binomial (Clopper-Pearson) interval of a share";
  }
  return s;
}

std::vector<std::size_t> summary_ranks(std::size_t n) {
  const double nn = static_cast<double>(n);
  std::vector<std::size_t> ranks = {0, n - 1};
  std::vector<double> levels = {1.0 / (nn + 1.0), nn / (nn + 1.0)};
  for (const SummaryQuantile& q : summary_quantiles()) levels.push_back(q.p);
  for (const double p : levels) {
    const QuantileRanks r = quantile_ranks(n, p, true);
    ranks.push_back(r.lo_i);
    ranks.push_back(r.hi_i);
    if (r.ci_lo) ranks.push_back(*r.ci_lo);
    if (r.ci_hi) ranks.push_back(*r.ci_hi);
  }
  std::sort(ranks.begin(), ranks.end());
  ranks.erase(std::unique(ranks.begin(), ranks.end()), ranks.end());
  return ranks;
}

Summary summarize_from(const SummaryMoments& m, const std::function<double(std::size_t)>& at) {
  const std::size_t n = m.n;
  POISE_INVARIANT(n > 0, "summary of an empty sample");
  Summary s;
  s.n = n;
  const double nn = static_cast<double>(n);
  const double mean = m.mean;
  const double var = n > 1 ? m.m2 / (nn - 1.0) : 0.0;
  const double m4 = m.m4 / nn;
  // A spread at the level of the values' round-off (identical values summed in another order)
  // is no spread: 0, not 1e-15 printed as a result.
  const double sd =
      std::sqrt(var) <= 64.0 * std::numeric_limits<double>::epsilon() * std::fabs(mean) ? 0.0 : std::sqrt(var);
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
  for (const SummaryQuantile& q : summary_quantiles()) {
    Estimate& e = s.*q.field;
    e = quantile_at(quantile_ranks(n, q.p, true), at);
    note_missing_ends(e, n, q.p);
  }
  s.max.value = at(n - 1);
  s.max.lo = quantile_at(quantile_ranks(n, nn / (nn + 1.0), true), at).lo;
  s.max.note = "one-sided: the sample maximum has no distribution-free upper bound";
  s.min.value = at(0);
  s.min.hi = quantile_at(quantile_ranks(n, 1.0 / (nn + 1.0), true), at).hi;
  s.min.note = "one-sided: the sample minimum has no distribution-free lower bound";
  return s;
}

}  // namespace poise::sampling
