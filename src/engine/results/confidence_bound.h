#pragma once
/// Confidence bounds and intervals of the statistics a requirement or an optimization states
/// its limits on (statistic(): mean, std, min, max, p<q>, fraction_le/ge:<x>): the verdicts of
/// [[requirement]] (requirements.h), a chance constraint of `poise optimize` ("the upper 95%
/// bound of p99.73 <= 1 px") and its fresh-sample check.
///
/// Independent samples (monte_carlo, or any design without replicates):
///   p<q>       distribution-free order-statistic bound: the upper bound at confidence c is
///              X_(k) with k - 1 the smallest x where P(Binomial(n, q) <= x) >= c (so
///              P(X_(k) >= q-quantile) >= c); the lower bound mirrors it. None if n is too small.
///   mean       Student t: mean +- t(c, n-1) s / sqrt(n).
///   fraction   Clopper-Pearson (exact binomial): the share of units meeting a requirement.
///   std        chi-square, assuming normal values (reported, not accepted as a bound).
///   min, max   the sample extreme; no distribution-free bound exists on its far side.
/// Randomized replicates (lhs / sobol with replicate_size, whose points are not independent):
///   p<q>       Woodruff's bound (sampling::replicate_quantile_bound): the replicates' shares
///              below the pooled quantile, p +- t(c, R-1) x their standard error, mapped back
///              through the pooled order statistics; none past the pooled sample.
///   others     pooled statistic +- t(c, R-1) x the standard error of the R replicates' own
///              statistics, for every statistic but min and max.
///   (sampling::summarize_replicates does the same for its figures at 95%.)
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace poise::engine {

enum class BoundSide { kNone, kUpper, kLower };

struct BoundSpec {
  BoundSide side = BoundSide::kNone;
  double confidence = 0.95;  ///< one-sided
};

/// "value" (no bound), "upper95", "lower97.5", ... (confidence 50 < c < 100 percent).
/// Throws poise::Error naming what is accepted.
BoundSpec parse_bound(const std::string& text);
/// "upper95", "lower97.5", "value".
std::string to_string(const BoundSpec& bound);
/// "upper 95% bound"
std::string describe(const BoundSpec& bound);
/// Whether a one-sided bound of the statistic exists (mean, p<q>, fraction_le/ge:<x>).
bool bound_supported(const std::string& statistic);

/// The values of one output, with the replicate of each (empty: independent samples).
struct SampleSet {
  std::vector<double> values;
  std::vector<std::size_t> replicate;  ///< replicate of each value, or empty

  std::size_t replicates() const;  ///< distinct replicates holding >= 2 values (0: none)
};

/// The values of one output of an evaluation: replicate r = ok_index / replicate_size.
SampleSet sample_set(const std::vector<double>& values, const std::vector<std::size_t>& ok_index,
                     std::size_t replicate_size);

/// The one-sided bound of the statistic at the bound's confidence; nullopt if none exists
/// (too few samples for the order statistic, fewer than 2 replicates, min / max).
std::optional<double> one_sided_bound(const SampleSet& s, const std::string& statistic, const BoundSpec& bound);

struct Interval {
  double value = 0.0;
  std::optional<double> lo, hi;  ///< two-sided ends; a missing end does not exist
  std::string method;            ///< "order statistics", "replicates (4 x 1024)", ...
};

/// The statistic with its two-sided interval at `confidence` (0.95: 95%).
Interval interval(const SampleSet& s, const std::string& statistic, double confidence = 0.95);

}  // namespace poise::engine
