#pragma once
/// Statistics of a field: a value at each of `columns` points (grid points) for every sample,
/// too many to hold (10^6 samples x 169 points is 676 MB as float32). They are read back column
/// by column (samples.h5, wide_columns.h), on all threads, and never held whole:
///   per point  the quantiles asked for, of that point's values over the samples (as
///              sampling::quantile_value gives them);
///   pooled     the summary of every (sample, point) value with its 95% intervals
///              (sampling::summarize_from): mean and central moments by two passes, the order
///              statistics exactly, by a two-level radix selection over the float32 bit patterns
///              (pass 1 counts the upper 16 bits, pass 2 the lower 16 within the bins that hold
///              a wanted rank).
/// Per-point quantiles come from one radix sort of the column's order-preserving float keys.
/// Memory: three copies of one column per thread (the values, their keys, the sort's scratch;
/// 120 MB per thread at 10^7 samples) plus 0.5 MB of counts per thread and wanted bin.
/// Missing values (NaN: failed samples) are left out. Results do not depend on the thread count.
#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "sampling/statistics.h"

namespace poise::studies {

struct FieldStatistics {
  std::vector<std::vector<double>> per_point;  ///< [quantile][point]; NaN where a point has no value
  sampling::Summary pooled;                    ///< n = 0 when there is no value at all
};

/// `read_column(p, out)` fills `out` with every sample's value at point p; it is called from
/// several threads at once (twice per point).
FieldStatistics field_statistics(std::size_t columns,
                                 const std::function<void(std::size_t, std::vector<float>&)>& read_column,
                                 std::span<const double> quantiles, int threads);

}  // namespace poise::studies
