#pragma once
/// What `poise mass-properties` prints of its figures: text (each part in its file's unit,
/// then the assembly) or one JSON object (SI units).
#include <nlohmann/json.hpp>
#include <ostream>

#include "cli/mass_properties_parts.h"

namespace poise::cli::mass_properties {

nlohmann::json to_json(const Computed& c);
void print_text(const Computed& c, std::ostream& out);

}  // namespace poise::cli::mass_properties
