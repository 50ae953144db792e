#pragma once
/// Numbers in words for tables and sentences, one place for every report and terminal text.
#include <string>

namespace poise {

/// Three significant digits with trailing zeros kept ("1.00", "0.0450"); whole numbers at or
/// above 100 ("1234"); "nan" for a value that is not finite.
std::string short_number(double v);

}  // namespace poise
