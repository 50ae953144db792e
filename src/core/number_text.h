#pragma once
/// Numbers in words for tables and sentences, one place for every report and terminal text.
#include <optional>
#include <string>

namespace poise {

/// Three significant digits with trailing zeros kept ("1.00", "0.0450"); whole numbers at or
/// above 100 ("1234"); "nan" for a value that is not finite.
std::string short_number(double v);

/// A statistic and the ends of its interval, written at one decimal place: the place that gives
/// the interval's (narrower) half-width two significant digits, so the digits shown are the
/// digits the interval supports, and the value and its ends line up ("9.000 [8.911, 9.089]",
/// "1.13 [1.01, 1.23]", "20.7 [20.3, 21.0]"). No decimals for a half-width of 10 or more; at
/// most 7 significant digits in any of the three. Without a finite interval (a missing end, a
/// zero width) each number has 4 significant digits. A missing end is "".
struct IntervalText {
  std::string value, lo, hi;
};
IntervalText interval_text(double value, std::optional<double> lo, std::optional<double> hi);

}  // namespace poise
