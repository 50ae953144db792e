#include "core/format.h"

#include <cmath>

namespace poise {

std::string significant(double v, int digits) { return fmt::format("{:.{}g}", v, digits); }

std::string significant_or(double v, std::string_view otherwise, int digits) {
  return std::isfinite(v) ? significant(v, digits) : std::string(otherwise);
}

std::string fixed(double v, int decimals) { return fmt::format("{:.{}f}", v, decimals); }

std::string signed_percent(double fraction, int decimals) {
  std::string s = fmt::format("{:+.{}f}", 100.0 * fraction, decimals);
  if (s[0] == '-' && s.find_first_not_of("0.", 1) == std::string::npos) s[0] = '+';  // "-0.0" rounded from below
  return s + '%';
}

}  // namespace poise
