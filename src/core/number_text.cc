#include "core/number_text.h"

#include <algorithm>
#include <cmath>

#include "core/format.h"

namespace poise {

std::string short_number(double v) {
  if (!std::isfinite(v)) return "nan";
  const double a = std::fabs(v);
  if (a >= 100.0 || a == 0.0) return fixed(v, 0);
  std::string s = fmt::format("{:#.3g}", v);  // keeps trailing zeros: 1.00, not 1
  // 99.95 to 99.999... rounds up to three whole digits: printf's "%#.3g" wrote "100.", fmt 9
  // writes "100.0"; the text stays "100.".
  if (s == "100.0" || s == "-100.0") s.pop_back();
  return s;
}

namespace {

// Four significant digits; any nan is "nan" (whatever its sign bit), inf "inf" or "-inf".
std::string four_digits(double v) {
  if (!std::isfinite(v)) return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
  return significant(v, 4);
}

std::string with_decimals(double v, int decimals) {
  if (!std::isfinite(v)) return four_digits(v);
  std::string s = fixed(v, decimals);
  if (s == "-0" || (s.rfind("-0.", 0) == 0 && s.find_first_not_of("0.", 1) == std::string::npos)) s.erase(0, 1);
  return s;
}

}  // namespace

IntervalText interval_text(double value, std::optional<double> lo, std::optional<double> hi) {
  IntervalText t;
  double half = INFINITY;
  if (lo && std::isfinite(*lo)) half = std::min(half, std::fabs(value - *lo));
  if (hi && std::isfinite(*hi)) half = std::min(half, std::fabs(*hi - value));
  if (lo && hi && std::isfinite(*lo) && std::isfinite(*hi) && !(half > 0.0)) half = 0.5 * std::fabs(*hi - *lo);
  if (!std::isfinite(value) || !std::isfinite(half) || !(half > 0.0)) {
    t.value = four_digits(value);
    if (lo) t.lo = four_digits(*lo);
    if (hi) t.hi = four_digits(*hi);
    return t;
  }
  int decimals = std::max(0, 1 - static_cast<int>(std::floor(std::log10(half))));
  // At most 7 significant digits in the largest of the three.
  double largest = std::fabs(value);
  if (lo) largest = std::max(largest, std::fabs(*lo));
  if (hi) largest = std::max(largest, std::fabs(*hi));
  if (largest > 0.0) {
    const int leading = static_cast<int>(std::floor(std::log10(largest))) + 1;  // digits before the point
    decimals = std::min(decimals, std::max(0, 7 - leading));
  }
  t.value = with_decimals(value, decimals);
  if (lo) t.lo = with_decimals(*lo, decimals);
  if (hi) t.hi = with_decimals(*hi, decimals);
  return t;
}

}  // namespace poise
