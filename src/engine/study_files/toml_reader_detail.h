#pragma once
/// Helpers shared by the files of the TOML reader (toml_reader.cc, toml_file.cc,
/// toml_key_check.cc); not part of its interface.
#include <toml++/toml.h>

#include <string>

#include "core/error.h"

namespace poise::engine::detail {

/// Where node n is in file (line and column; 0, 0 without a node).
SourceLocation location_of(const std::string& file, const toml::node* n);

/// "group[3].load[0].mass" -> "group[].load[].mass": the schema's form of a path.
std::string schema_path(const std::string& path);

}  // namespace poise::engine::detail
