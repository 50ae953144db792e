#pragma once
/// Summary statistics with 95% confidence intervals, for a reviewer who must know
/// how much of a figure is sampling noise.
///   mean   : mean +- t(0.975, n-1) s / sqrt(n)
///   std    : asymptotic, distribution-free: Var(s^2) ~ (m4 - s^4 (n-3)/(n-1)) / n, delta method
///   pXX    : point value: Hyndman & Fan (1996) definition 8, rank h = (n + 1/3) p + 1/3
///            (1-based, linear between order statistics, clamped to the sample's ends): median-
///            unbiased for any continuous distribution, so that P(estimate < true quantile) is
///            about 1/2 even far in the tail. (Definition 7, h = (n - 1) p + 1, the common default,
///            runs low in the tail: at n = 1024 its p99.73 lies below the true value in about 65%
///            of runs; tests/sampling/statistics_test.cc measures both.)
///            Interval: order statistics from the exact binomial(n, p) distribution, distribution-
///            free. An end that needs more samples than n is missing (null) and `note` says so:
///            the upper end of pXX needs n >= ln(0.025) / ln(p) (1365 for p99.73, 72 for p95).
///   max    : the sample maximum; lower end = lower order-statistic bound of the quantile
///            n/(n+1), upper end unknown (no distribution-free upper bound exists).
///   min    : its mirror: the sample minimum; upper end = upper order-statistic bound of the
///            quantile 1/(n+1), lower end unknown.
/// The quantiles are p0.135, p2.5, p50, p95, p97.5, p99.73 and p99.865 (summary_quantiles()):
/// the lower tail beside the upper one, for two-sided specifications (a gap between two limits;
/// p0.135 and p99.865 are the natural process limits mean -+ 3 sigma of a normal output).
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
  /// "" or how to read the interval: "one-sided: ..." when an end is missing and why,
  /// "approximate: ..." when the interval rests on too few samples to be trusted at 95%.
  std::string note;
};

struct Summary {
  std::size_t n = 0;
  Estimate mean, std, min, p0_135, p2_5, p50, p95, p97_5, p99_73, p99_865, max;
};

/// A quantile a Summary holds: its name in summary.json ("p99_73"), its level (0.9973) and
/// its member.
struct SummaryQuantile {
  const char* name;
  double p;
  Estimate Summary::*field;
};
/// Every quantile of a Summary, in increasing level.
std::span<const SummaryQuantile> summary_quantiles();

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

/// Summary of values from independent randomized replicates (design.h replicate_size), for
/// lhs and scrambled Sobol points, which are not independent within a replicate. Each figure
/// is the pooled one (R >= 2 replicates of 2 or more values; otherwise no interval):
///   mean, std : pooled +- t(0.975, R-1) x the standard error of the R replicates' own figures.
///   pXX       : Woodruff's interval (Woodruff 1952, JASA 47:635; with replicate variances as in
///               survey sampling, Francisco & Fuller 1991, Ann. Stat. 19:454). At the pooled
///               estimate q each replicate r gives F_r = its share of values below q (ties
///               count half); the share's 95% interval p +- t(0.975, R-1) sd(F_r) / sqrt(R) is
///               mapped back through the pooled order statistics (ranks by definition 8,
///               rounded outwards). Not each replicate's own quantile: a replicate of 64 points
///               has its "p99.73" at its maximum, and their spread then says nothing about
///               the pooled figure (an interval that covered in 70% of runs, issue 21).
///               An end past the pooled sample is missing ("one-sided"); when
///               replicate_size x min(p, 1 - p) < kMinTailPerReplicate the interval is flagged
///               "approximate" (its spread is a spread of a few counts per replicate).
///   max       : keeps its order-statistic bound.
Summary summarize_replicates(std::span<const double> values, std::span<const std::size_t> replicate_of);

/// One end of Woodruff's interval above (upper) or below the p-quantile from replicates at
/// one-sided confidence `confidence` (t(confidence, R-1)); nullopt with fewer than 2
/// replicates of 2 or more values, or when the end lies past the pooled sample. At 0.975 the
/// ends of summarize_replicates' 95% interval.
std::optional<double> replicate_quantile_bound(std::span<const double> values,
                                               std::span<const std::size_t> replicate_of, double p, double confidence,
                                               bool upper);

/// Expected samples per replicate beyond a quantile below which its replicate interval is
/// approximate, and `--until` on it is refused.
inline constexpr double kMinTailPerReplicate = 10.0;

/// Smallest n at which the order-statistic 95% interval of the p-quantile has an upper end
/// (ceil(ln 0.025 / ln p): 1365 for p = 0.9973).
std::size_t samples_for_upper_end(double p);

/// Quantile of sorted values (definition 8, see above) with its binomial CI.
Estimate quantile_sorted(std::span<const double> sorted, double p);

/// Quantile value only (no CI) of unsorted data, which it partially reorders; O(n).
double quantile_value(std::span<double> data, double p);

/// Quantile value only (no CI) of n ascending values, the k-th (0-based) given by
/// `sorted_at(k)`: equal to quantile_value of the same values; O(1).
double quantile_value_sorted(std::size_t n, double p, const std::function<double(std::size_t)>& sorted_at);

/// Fraction successes/n with the Wilson 95% interval.
Estimate fraction_wilson(std::size_t successes, std::size_t n);

}  // namespace poise::sampling
