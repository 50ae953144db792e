#include "core/number_text.h"

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

}  // namespace poise
