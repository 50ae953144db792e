#pragma once
/// Sobol sensitivity indices of a study's outputs (`poise sensitivity`): which tolerance
/// drives each output. The run's samples are in the Saltelli layout (sampling/design.h):
/// base rows j = 0..N-1 of A, B and A with group g from B; sampling/sensitivity.h estimates
/// the first-order (Saltelli 2010) and total (Jansen 1999) indices with bootstrap intervals.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace poise::engine {

/// The model's tolerances over the design dimensions, from the tolerance key of each
/// (InputColumn::tolerance; "" = the dimension is a tolerance of its own, named by `names`).
struct ToleranceGroups {
  std::vector<std::string> names;              ///< tolerance keys, in order of first dimension
  std::vector<std::vector<std::size_t>> dims;  ///< the dimensions of each
  /// The groups of more than one dimension: the Saltelli layout's extra groups.
  std::vector<std::vector<std::size_t>> closed_groups() const;
};
ToleranceGroups tolerance_groups(const std::vector<std::string>& dimension_names,
                                 const std::vector<std::string>& tolerance_of);

/// values[output][sample index] (NaN for a failed sample), samples = base x (groups +
/// closed groups of `tolerances` + 2), groups = one per design dimension (+ the within-sample
/// randomness). Returns {"base_rows", "groups", "method", "outputs": {name: {"variance",
/// "first_sum", "indices": [{"group", "first", "total", "rows_used"}] (per column, sorted by
/// total, largest first), "tolerances": [same, per tolerance key: the closed group index of
/// its columns taken together (a tolerance of one column: that column's), sorted],
/// "tolerance_first_sum", "note"}}}.
nlohmann::json sensitivity_json(const std::vector<std::string>& outputs, const std::vector<std::string>& groups,
                                std::size_t base, const std::vector<std::vector<double>>& values, std::uint64_t seed,
                                const ToleranceGroups& tolerances = {});

}  // namespace poise::engine
