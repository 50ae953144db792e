#pragma once
/// One formatting layer for every text with numbers in it: fmt::format ("{:.4g}", "{:+.2f}",
/// "{:<22}") for sentences and lines, and the number helpers below, one name per way of writing a
/// number. Each writes exactly what the printf conversion it names wrote ("%.*g", "%.*f").
#include <fmt/format.h>

#include <string>
#include <string_view>

namespace poise {

/// v with `digits` significant digits, the shorter of fixed and exponent form, as printf's "%.*g"
/// ("0.1235", "1.235e+06", "-0", "nan", "inf").
std::string significant(double v, int digits = 4);

/// significant(v, digits) for a finite v; `otherwise` (a table's "&ndash;", a text's "n/a") for nan and inf.
std::string significant_or(double v, std::string_view otherwise, int digits = 4);

/// v with `decimals` digits after the point, as printf's "%.*f" ("1.50", "-0.00", "1235").
std::string fixed(double v, int decimals);

/// A fraction as a percent with its sign and `decimals` places ("+12.3%", "-0.4%"); a percent that
/// rounds to zero is "+0.0%", never "-0.0%".
std::string signed_percent(double fraction, int decimals = 1);

}  // namespace poise
