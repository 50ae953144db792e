#include "budget/field_grid.h"

#include <algorithm>

#include "core/error.h"

namespace poise::budget {

std::vector<double> field_axis(double lo, double hi, std::size_t points) {
  require(points >= 2 && lo <= hi, "field_axis: needs lo <= hi and at least 2 points");
  if (lo == hi) return {lo};
  std::vector<double> v(points);
  for (std::size_t i = 0; i < points; ++i) {
    v[i] = lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(points - 1);
  }
  v.back() = hi;  // exact end, whatever the rounding
  // Zero inside the range: snap a point that is zero up to rounding, else insert it.
  if (lo < 0.0 && hi > 0.0) {
    const double tiny = 1e-12 * (hi - lo);
    auto near = std::find_if(v.begin(), v.end(), [&](double x) { return std::abs(x) <= tiny; });
    if (near != v.end()) {
      *near = 0.0;
    } else {
      v.insert(std::upper_bound(v.begin(), v.end(), 0.0), 0.0);
    }
  }
  return v;
}

FieldGrid::FieldGrid(const std::vector<FieldVariable>& field, std::size_t points) {
  for (const auto& f : field) {
    axes_.push_back(field_axis(f.lo, f.hi, points));
    size_ *= axes_.back().size();
    require(size_ <= kMaxFieldGridPoints, "the field grid has more than " + std::to_string(kMaxFieldGridPoints) +
                                              " points: fewer field_points or variables");
  }
}

void FieldGrid::point(std::size_t i, std::vector<double>& out) const {
  out.resize(axes_.size());
  // Mixed radix, the last variable fastest.
  for (std::size_t k = axes_.size(); k-- > 0;) {
    const std::size_t n = axes_[k].size();
    out[k] = axes_[k][i % n];
    i /= n;
  }
}

}  // namespace poise::budget
