#pragma once
/// The keys of a study kind's files, from the code's own reading (TomlReader records every
/// key it is asked for: KeySchemaRecorder), so the reference cannot drift from the program.
/// `poise keys KIND` prints it.
#include <string>
#include <vector>

#include "engine/study_files/toml_reader.h"

namespace poise::engine {

struct KindKeys {
  std::vector<KeyDoc> study;  ///< keys of a study file of the kind (shared and the kind's own)
  std::vector<KeyDoc> model;  ///< keys of the model file it names
};

/// Reads an empty study of `kind` and its model under a KeySchemaRecorder. Keys read only
/// on a branch the empty file does not take (e.g. per experiment type) may be missing; the
/// kinds read such keys whenever the schema is recorded. Throws poise::Error for an unknown kind.
KindKeys kind_keys(const std::string& kind);

/// The keys as text: one line per key, grouped by table, with what is expected and the default.
std::string keys_text(const std::string& kind, const KindKeys& keys);

}  // namespace poise::engine
