#include "estimators/residual_plan.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/format.h"
#include "estimators/sine_fit.h"

namespace poise::estimators::detail {

// Spearman rank correlation of the angle with the measurement order.
double order_angle_correlation(const TorqueTable& table, const std::vector<std::size_t>& order) {
  const std::size_t n = order.size();
  std::vector<std::size_t> by_angle(n);
  std::iota(by_angle.begin(), by_angle.end(), std::size_t{0});
  std::stable_sort(by_angle.begin(), by_angle.end(),
                   [&](auto a, auto b) { return table.theta_rad[a] < table.theta_rad[b]; });
  std::vector<double> rank_angle(n), rank_time(n);
  for (std::size_t k = 0; k < n; ++k) rank_angle[by_angle[k]] = static_cast<double>(k);
  for (std::size_t k = 0; k < n; ++k) rank_time[order[k]] = static_cast<double>(k);
  const double mean = 0.5 * static_cast<double>(n - 1);
  double sxy = 0.0, sxx = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sxy += (rank_angle[i] - mean) * (rank_time[i] - mean);
    sxx += (rank_time[i] - mean) * (rank_time[i] - mean);
  }
  return sxx > 0.0 ? sxy / sxx : 0.0;
}

bool monotone_plan(const TorqueTable& table, const std::vector<std::size_t>& order) {
  return std::abs(order_angle_correlation(table, order)) > 0.95;
}

std::string describe_plan(const TorqueTable& table, const std::vector<std::size_t>& order, bool monotone) {
  const std::size_t positions = count_distinct_angles(table.theta_rad);
  const long up = std::count(table.sweep.begin(), table.sweep.end(), 1);
  const long down = std::count(table.sweep.begin(), table.sweep.end(), -1);
  return fmt::format(
      "{} points at {} positions{}; {}; measurement order from {}; rank correlation "
      "of angle with measurement order {:.2f}{}",
      table.size(), positions, positions < table.size() ? " (some repeated)" : "",
      table.sweep.empty()    ? "no sweep column"
      : (up > 0 && down > 0) ? "both directions (" + std::to_string(up) + " +, " + std::to_string(down) + " -)"
                             : "one direction",
      table.time_s.empty() ? "the row order" : "time_s", order_angle_correlation(table, order),
      monotone ? ": time order follows angle order, so any smooth function of time is "
                 "one of angle (harmonics, drifts and correlated noise are confounded)"
               : "");
}

}  // namespace poise::estimators::detail
