#include "core/number_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace poise {

std::string short_number(double v) {
  if (!std::isfinite(v)) return "nan";
  char buf[32];
  const double a = std::fabs(v);
  if (a >= 100.0 || a == 0.0) {
    std::snprintf(buf, sizeof buf, "%.0f", v);
  } else {
    std::snprintf(buf, sizeof buf, "%#.3g", v);  // keeps trailing zeros: 1.00, not 1
  }
  return buf;
}

namespace {

std::string significant(double v, int digits) {
  if (!std::isfinite(v)) return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string with_decimals(double v, int decimals) {
  if (!std::isfinite(v)) return significant(v, 4);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s = buf;
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
    t.value = significant(value, 4);
    if (lo) t.lo = significant(*lo, 4);
    if (hi) t.hi = significant(*hi, 4);
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
