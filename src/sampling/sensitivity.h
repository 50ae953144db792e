#pragma once
/// Variance-based sensitivity: Sobol first-order and total indices of one scalar output
/// from Saltelli's radial design, with percentile-bootstrap 95% confidence intervals.
///
/// Layout. k input groups (a group = one or more input dimensions). For N base rows
/// j = 0..N-1 the model was evaluated at A_j (all inputs from matrix A), B_j (all from an
/// independent matrix B) and AB^(g)_j, g = 0..k-1: A_j with the inputs of group g taken
/// from B_j. fA[j], fB[j], fAB[g][j] are the output values there; N (k + 2) evaluations.
///
/// Rows. A value that is not finite (NaN: the evaluation failed; or +-inf) drops its row
/// from every estimate that uses it:
///   base rows R   : fA[j] and fB[j] finite, n = |R|              (the total variance)
///   group rows R_g: j in R and fAB[g][j] finite, n_g = |R_g|      (the indices of group g)
///
/// Estimators (all values first centred by m, the mean of the 2n pooled fA, fB over R;
/// the indices are invariant to a shift of f in expectation, and centring keeps an output
/// with a large offset from inflating the variance of V_g and from cancellation):
///   total variance  V    = 1/(2n - 1) sum_{j in R} [(fA_j - m)^2 + (fB_j - m)^2]
///   first order     V_g  = 1/n_g sum_{j in R_g} (fB_j - m) (fAB^(g)_j - fA_j)
///                   (Saltelli et al. 2010, Comput. Phys. Commun. 181:259-270, Table 2 (b))
///   total           VT_g = 1/(2 n_g) sum_{j in R_g} (fA_j - fAB^(g)_j)^2
///                   (Jansen 1999, Comput. Phys. Commun. 117:35-43; Saltelli 2010 Table 2 (f))
///   S_g = V_g / V,  ST_g = VT_g / V,  first_sum = sum_g S_g (share of the variance
///   explained by first-order effects; 1 - first_sum is the share of interactions).
/// S_g can come out slightly negative or above ST_g by sampling noise; it is not clipped.
/// A group whose inputs have no effect gives fAB^(g) == fA, hence S_g = ST_g = 0 exactly.
///
/// Bootstrap. Resample r = 0..B-1 draws n rows of R with replacement, from
/// RandomStream(seed, StreamId::kBootstrap, r) (deterministic, independent of threads), and
/// recomputes everything on those rows (m, V and every V_g, VT_g: one resample for numerator
/// and denominator). Reported: value = the estimate on the data, lo/hi = the 2.5% and
/// 97.5% quantiles of the B replicates (percentile interval), *_se = the standard deviation
/// of the replicates. Replicates that are not finite (a resample without a row of R_g) are
/// left out. Intervals assume independent base rows (plain Monte Carlo A and B); for
/// Latin hypercube or Sobol base matrices they are usually conservative (those designs
/// tend to have lower variance), not guaranteed.
///
/// Undefined indices are NaN with a reason in `note` (no exception): fewer than 2 base rows;
/// a constant output, i.e. sqrt(V) <= kConstantOutputTolerance * max_{R} |f| (includes
/// V = 0); a group with no usable row (then first_sum is NaN too). Cost O(B n k),
/// single-threaded: about 0.3 s for n = 10^4, k = 40, B = 1000; 0.15 s for n = 2^14, k = 3.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "sampling/statistics.h"

namespace poise::sampling {

/// Relative standard deviation below which an output counts as constant (rounding noise).
inline constexpr double kConstantOutputTolerance = 1e-10;

struct SobolIndex {
  Estimate first;             ///< S_g with its 95% percentile-bootstrap interval
  Estimate total;             ///< ST_g with its 95% percentile-bootstrap interval
  double first_se = 0.0;      ///< bootstrap standard error of S_g (0 without bootstrap)
  double total_se = 0.0;      ///< bootstrap standard error of ST_g
  std::size_t rows_used = 0;  ///< n_g: base rows with fA, fB and fAB^(g) finite
};

struct SobolResult {
  std::vector<SobolIndex> groups;  ///< one per group, in the order of fAB
  Estimate first_sum;              ///< sum_g S_g with its interval
  double first_sum_se = 0.0;       ///< bootstrap standard error of first_sum
  double variance = 0.0;           ///< V, the total variance of the output
  std::size_t n = 0;               ///< base rows used for V (fA and fB finite)
  std::string note;                ///< empty, or why some indices are NaN
};

/// Sobol indices of one output. fA, fB and every fAB[g] must have the same size N (throws
/// poise::Error otherwise, or if fAB is empty). bootstrap_resamples = 0 gives the
/// estimates without intervals (lo/hi empty, se 0).
SobolResult sobol_indices(std::span<const double> fA, std::span<const double> fB,
                          const std::vector<std::span<const double>>& fAB, std::uint64_t seed,
                          std::size_t bootstrap_resamples = 1000);

}  // namespace poise::sampling
