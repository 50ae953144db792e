#pragma once
/// Overrides of model-file values by dotted key ("yaw.bearing_span" -> "100 mm"), applied
/// to the parsed TOML before validation, so an override is checked like the file itself.
/// A key that does not exist in the file is an error (a typo must not pass silently).
#include <map>
#include <memory>
#include <string>

#include "engine/study_files/toml_reader.h"

namespace poise::engine {

/// What an override of a key the model file lacks is refused with (the start of its
/// "expected" text; "; did you mean '<key>'?" may follow): callers that validate many values
/// of one key (a sweep) recognise it by this, to say it once for the key.
inline constexpr const char* kUnknownModelKey = "an override of a key that exists in the model file";

void apply_overrides(toml::table& root, const std::map<std::string, std::string>& overrides, ReadContext& ctx);

/// A model file parsed, with the overrides applied and its reading context.
struct ModelDocument {
  toml::table doc;
  std::shared_ptr<ReadContext> ctx;
};
ModelDocument open_model_file(const std::string& path, const std::map<std::string, std::string>& overrides);

/// The [model] table every model file starts with; `kind` is the only accepted kind. Also
/// reads the file's [[reference]] tables (their errors are the file's).
struct ModelHeader {
  std::string file;  ///< the model file's path
  std::string name, title, source;
};
ModelHeader read_model_header(TomlReader& root, const std::string& kind);

}  // namespace poise::engine
