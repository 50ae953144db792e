#pragma once
/// Sobol sensitivity indices of a study's outputs (`poise sensitivity`): which tolerance
/// drives each output. The run's samples are in the Saltelli layout (sampling/design.h):
/// base rows j = 0..N-1 of A, B and A with group g from B; sampling/sensitivity.h estimates
/// the first-order (Saltelli 2010) and total (Jansen 1999) indices with bootstrap intervals.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace poise::studies {

/// values[output][sample index] (NaN for a failed sample), samples = base x (groups + 2).
/// Returns {"base_rows", "groups", "method", "outputs": {name: {"variance", "first_sum",
/// "indices": [{"group", "first", "total", "rows_used"}] (sorted by total, largest first),
/// "note"}}}.
nlohmann::json sensitivity_json(const std::vector<std::string>& outputs, const std::vector<std::string>& groups,
                                std::size_t base, const std::vector<std::vector<double>>& values, std::uint64_t seed);

/// report.html section: per output, the groups that drive it.
std::string sensitivity_html(const nlohmann::json& sensitivity);

}  // namespace poise::studies
