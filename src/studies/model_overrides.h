#pragma once
/// Overrides of model-file values by dotted key ("yaw.bearing_span" -> "100 mm"), applied
/// to the parsed TOML before validation, so an override is checked like the file itself.
/// A key that does not exist in the file is an error (a typo must not pass silently).
#include <map>
#include <string>

#include "studies/toml_reader.h"

namespace poise::studies {

void apply_overrides(toml::table& root, const std::map<std::string, std::string>& overrides,
                     ReadContext& ctx);

}  // namespace poise::studies
