#include "engine/report/budget_numbers.h"

#include <algorithm>
#include <cmath>

#include "core/format.h"

namespace poise::engine {

using nlohmann::json;

std::string budget_number(const json& v) {
  if (v.is_null()) return "-";
  const double x = v.get<double>();
  if (x != 0.0 && (std::abs(x) >= 1e5 || std::abs(x) < 1e-3)) return significant(x);
  const int digits = x == 0.0 ? 0 : std::max(0, 3 - static_cast<int>(std::floor(std::log10(std::abs(x)))));
  return fixed(x, digits);
}

std::string recomputed_text(const json& it, const std::string& unit) {
  if (it.contains("recomputed_min")) {
    return budget_number(it["recomputed_min"]) + " to " + budget_number(it["recomputed_max"]) + " " + unit +
           " over the field";
  }
  if (it.contains("recomputed")) return budget_number(it["recomputed"]) + " " + unit;
  if (it.contains("least")) {
    return budget_number(it["least"]) + " to " + budget_number(it["greatest"]) + " " + unit;
  }
  return "-";
}

std::string declared_text(const json& d, const std::string& unit) {
  if (d.is_null()) return "none";
  if (d.is_array()) return budget_number(d[0]) + " to " + budget_number(d[1]) + " " + unit;
  return budget_number(d) + " " + unit;
}

}  // namespace poise::engine
