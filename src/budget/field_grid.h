#pragma once
/// The grid over the [field] variables on which every gain is evaluated: per variable
/// `points` values evenly spaced from its least to its greatest end, plus zero where zero is
/// inside the range and not already a point (a gain such as tan(pitch) or cos(yaw) has its
/// extreme there). The grid is the product of the variables' points; with no variable it is
/// one empty point.
#include <cstddef>
#include <vector>

#include "budget/budget_file.h"

namespace poise::budget {

/// Points of one variable: ends, evenly spaced interior points, and zero where in range.
std::vector<double> field_axis(double lo, double hi, std::size_t points);

class FieldGrid {
 public:
  FieldGrid(const std::vector<FieldVariable>& field, std::size_t points);
  std::size_t size() const { return size_; }
  /// The i-th point (one SI value per variable, in [field] order), i in [0, size()).
  void point(std::size_t i, std::vector<double>& out) const;
  const std::vector<std::vector<double>>& axes() const { return axes_; }

 private:
  std::vector<std::vector<double>> axes_;
  std::size_t size_ = 1;
};

/// Largest number of grid points a budget may ask for (points^variables).
inline constexpr std::size_t kMaxFieldGridPoints = 1'000'000;

}  // namespace poise::budget
