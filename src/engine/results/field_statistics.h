#pragma once
/// Statistics of a field: a value at each of `columns` points (grid points) for every sample,
/// too many to hold (10^6 samples x 169 points is 676 MB as float32). They come column by
/// column, on all threads: read back from samples.h5 (wide_columns.h), or from the writer's
/// copy in memory when the run is small enough to keep one; this never copies them whole:
///   per point  the quantiles asked for, of that point's values over the samples (as
///              sampling::quantile_value gives them);
///   pooled     the summary of every (sample, point) value with its 95% intervals
///              (sampling::summarize_from): mean and central moments by two passes, the order
///              statistics exactly, by a two-level radix selection over the float32 bit patterns
///              (pass 1 counts the upper 16 bits; pass 2 collects and sorts the values of the
///              bins that hold a wanted rank, or, when more than `collect_limit` values fall in
///              them (a field of few distinct values), counts their lower 16 bits).
/// Per-point quantiles come from one radix sort of the column's order-preserving float keys.
/// Memory: up to three copies of one column per thread (the values, their keys, the sort's scratch;
/// 120 MB per thread at 10^7 samples), 0.5 MB of counts per thread, and at most 4M collected
/// values (16 MB, three times that while they are sorted; else 0.5 MB of counts per thread and
/// wanted bin).
/// Missing values (NaN: failed samples) are left out. Results do not depend on the thread count.
/// Shared among the ranks of an MPI run (FieldShare), each rank reads and sorts its own range of
/// points, and the ranks exchange their points' figures, counts and collected values twice
/// (after each pass); every sum is still taken in point order, so every rank gets one process's
/// results, bit for bit.
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "sampling/statistics.h"

namespace poise::engine {

struct FieldStatistics {
  std::vector<std::vector<double>> per_point;  ///< [quantile][point]; NaN where a point has no value
  sampling::Summary pooled;                    ///< n = 0 when there is no value at all
};

/// `column(p, scratch)` gives every sample's value at point p: a view of values it holds, or of
/// `scratch` after filling it (a column read from a file). It is called from several threads at
/// once (twice per point), each with its own scratch; the view is used before the next call.
using FieldColumnSource = std::function<std::span<const float>(std::size_t p, std::vector<float>& scratch)>;
inline constexpr std::size_t kFieldCollectLimit = std::size_t{1} << 22;  ///< 16 MB of keys

/// The ranks of an MPI run computing a field's statistics together: rank r takes points
/// [columns r / ranks, columns (r + 1) / ranks); `all_gather` hands every rank's bytes to
/// each, in rank order (sampling::Cluster::all_gather). Every rank must call field_statistics.
struct FieldShare {
  int rank = 0, ranks = 1;
  std::function<std::vector<std::string>(const std::string&)> all_gather;
};

FieldStatistics field_statistics(std::size_t columns, const FieldColumnSource& column,
                                 std::span<const double> quantiles, int threads,
                                 std::size_t collect_limit = kFieldCollectLimit, const FieldShare* share = nullptr);

}  // namespace poise::engine
