#pragma once
/// What `poise mass-properties` prints of its figures: text (each part in its file's unit,
/// then the assembly) or one JSON object (SI units).
#include <nlohmann/json.hpp>
#include <ostream>

#include "geometry/mesh_parts.h"

namespace poise::cli::mass_properties {

nlohmann::json to_json(const geometry::MeshParts& c);
void print_text(const geometry::MeshParts& c, std::ostream& out);

}  // namespace poise::cli::mass_properties
