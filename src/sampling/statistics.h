#pragma once
/// Summary statistics with 95% confidence intervals, for a reviewer who must know
/// how much of a figure is sampling noise.
///   mean   : mean +- t(0.975, n-1) s / sqrt(n)
///   std    : asymptotic, distribution-free: Var(s^2) ~ (m4 - s^4 (n-3)/(n-1)) / n, delta method
///   pXX    : order-statistic interval from the exact binomial(n, p) distribution; distribution-
///            free. An end that needs more samples than n is reported as missing (null).
///   max    : the sample maximum; lower end = lower order-statistic bound of the quantile
///            n/(n+1), upper end unknown (no distribution-free upper bound exists).
///   fraction (of successes): Wilson score interval.
/// Intervals assume independent samples; for Latin hypercube and Sobol designs they are
/// conservative for the mean (those designs lower its variance) but not necessarily for tail
/// quantiles: randomized replicates (summarize_replicates) give honest intervals there.
#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace poise::sampling {

struct Estimate {
  double value = 0.0;
  std::optional<double> lo;  ///< lower end of the 95% CI, if it exists
  std::optional<double> hi;  ///< upper end of the 95% CI, if it exists
};

struct Summary {
  std::size_t n = 0;
  Estimate mean, std, p50, p95, p99_73, max;
};

/// Summary of the values (order does not matter). Throws if values is empty.
Summary summarize(std::span<const double> values);

/// What summarize() needs of n values, for values too many to hold at once (a field over
/// every sample, read back column by column): their mean, the sums of squared and fourth-power
/// deviations from it, and the order statistics at summary_ranks(n).
struct SummaryMoments {
  std::size_t n = 0;
  double mean = 0.0, m2 = 0.0, m4 = 0.0;  ///< m2 = sum (x - mean)^2, m4 = sum (x - mean)^4
};
/// The 0-based ranks (sorted, unique) of the order statistics a summary of n values uses.
std::vector<std::size_t> summary_ranks(std::size_t n);
/// The summary from the moments and `at(k)` = the k-th smallest value, k in summary_ranks(n);
/// the same figures and intervals as summarize() of the values.
Summary summarize_from(const SummaryMoments& m, const std::function<double(std::size_t)>& at);

/// Summary of values from independent randomized replicates (design.h replicate_size):
/// each figure is the pooled one, its 95% interval pooled +- t(0.975, R-1) x the standard
/// error of the R replicates' own figures (R >= 2 replicates of 2 or more values; otherwise
/// no interval). Honest for lhs and scrambled Sobol points, which are not independent
/// within a replicate. The max keeps its order-statistic bound.
Summary summarize_replicates(std::span<const double> values, std::span<const std::size_t> replicate_of);

/// Quantile of sorted values (type 7 / linear interpolation) with its binomial CI.
Estimate quantile_sorted(std::span<const double> sorted, double p);

/// Quantile value only (no CI) of unsorted data, which it partially reorders; O(n).
double quantile_value(std::span<double> data, double p);

/// Fraction successes/n with the Wilson 95% interval.
Estimate fraction_wilson(std::size_t successes, std::size_t n);

}  // namespace poise::sampling
