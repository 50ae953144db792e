#pragma once
/// Strict reading of study and model files (TOML, via toml++).
///
/// Every value is read through a TomlReader, which records which keys were used;
/// finish() then refuses every key nobody read ("unknown key"), with its line. Errors
/// are collected, not thrown one by one, so a person sees every problem of a file at
/// once; finish() throws a ValidationError listing them all. Nothing runs until the
/// whole file validates.
#include <toml++/toml.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/units.h"

namespace poise::engine {

/// Every error found in one or more files.
class ValidationError : public Error {
 public:
  explicit ValidationError(std::vector<InputError> errors);
  const std::vector<InputError>& errors() const { return errors_; }

 private:
  std::vector<InputError> errors_;
};

/// Largest study or model file read (a bigger one is refused, not loaded into memory).
inline constexpr std::uintmax_t kMaxInputFileBytes = std::uintmax_t{64} << 20;

/// Parses a TOML file; syntax errors become a ValidationError with file:line:col. A path
/// that is not a regular file (directory, device, FIFO) or is larger than
/// kMaxInputFileBytes is refused with a ValidationError.
toml::table parse_toml_file(const std::string& path);

/// A key a reader asked for: the code's own schema of a file (`poise keys`, "did you mean").
struct KeyDoc {
  std::string path;      ///< dotted, arrays of tables as "group[].load[].mass"
  std::string expected;  ///< what the value must be ("a length with its unit, e.g. \"1 mm\"")
  std::string fallback;  ///< the default when absent ("" = required or none)
  bool required = false;
};

/// Shared state of one file's reading: file name, used keys, keys asked for, errors.
struct ReadContext {
  std::string file;
  std::set<std::string> used;
  std::vector<InputError> errors;
  std::vector<KeyDoc> asked;  ///< every key asked for, in order (first ask of each path)
};

/// Records the schema of the files read on this thread while it lives (`poise keys`): every
/// file reads as an empty document (a study file as one whose [study] kind is `kind`), every
/// key asked for is recorded, and no error is reported.
class KeySchemaRecorder {
 public:
  explicit KeySchemaRecorder(std::string kind);
  ~KeySchemaRecorder();
  KeySchemaRecorder(const KeySchemaRecorder&) = delete;
  KeySchemaRecorder& operator=(const KeySchemaRecorder&) = delete;
  /// The recorder of this thread, or nullptr.
  static KeySchemaRecorder* active();
  const std::string& kind() const { return kind_; }
  /// Keys of the study file and of the model file, in the order they were asked for.
  std::vector<KeyDoc> study_keys, model_keys;
  /// Adds what a reading context asked (study or model file by its name).
  void add(const ReadContext& ctx);

 private:
  std::string kind_;
  KeySchemaRecorder* previous_;
};

/// The file name a study file is read under while a KeySchemaRecorder is active.
inline constexpr const char* kSchemaStudyFile = "(study file)";

/// A view of one table with a dotted path prefix ("yaw.perpendicularity").
class TomlReader {
 public:
  TomlReader(const toml::table& table, std::shared_ptr<ReadContext> ctx, std::string prefix = "");

  bool has(const std::string& key) const;
  /// has(key), or true while the schema is recorded (so that an optional section's keys are
  /// listed by `poise keys`): the gate of an optional table or key.
  bool has_or_schema(const std::string& key) const { return has(key) || schema_only(); }
  /// A sub-table; a missing required one is an error (an empty view is returned).
  TomlReader table(const std::string& key, bool required = true);
  /// Keys of this table in file order.
  std::vector<std::string> keys() const;
  /// An array of tables ([[key]]); missing = empty.
  std::vector<TomlReader> table_array(const std::string& key);

  std::string string(const std::string& key, std::optional<std::string> fallback = std::nullopt);
  /// A string from a fixed set of choices.
  std::string choice(const std::string& key, const std::vector<std::string>& choices,
                     std::optional<std::string> fallback = std::nullopt);
  /// A quantity "<number> <unit>" of the given dimension, in SI. check(value) returns an
  /// empty string if the value is acceptable, else what was expected ("a positive length").
  double quantity(const std::string& key, const units::Dimension& dim,
                  const std::function<std::string(double)>& check = {}, std::optional<double> fallback = std::nullopt);
  /// A plain number (dimensionless; a TOML integer or float, or a string "0.4").
  double number(const std::string& key, const std::function<std::string(double)>& check = {},
                std::optional<double> fallback = std::nullopt);
  /// A non-negative integer.
  std::int64_t integer(const std::string& key, std::int64_t min, std::int64_t max,
                       std::optional<std::int64_t> fallback = std::nullopt);
  bool boolean(const std::string& key, std::optional<bool> fallback = std::nullopt);
  /// An array of strings.
  std::vector<std::string> string_array(const std::string& key);

  /// Records an error at key (uses the key's line if present).
  void error(const std::string& key, const std::string& value, const std::string& expected);
  /// Marks every key of this table (and below) as used (for free-form tables).
  void accept_all();
  /// Reads the optional free-text keys `notes` and `source` (a model's reasoning).
  void accept_notes();
  /// Records that `key` is read here (its schema: what is expected, its default), for a
  /// key read from raw() rather than through an accessor, which records its own.
  void ask(const std::string& key, const std::string& expected, const std::string& fallback, bool required);
  /// Whether this reading only records the schema (KeySchemaRecorder).
  bool schema_only() const { return KeySchemaRecorder::active() != nullptr; }
  /// Line of key in the file (0 if absent).
  int line_of(const std::string& key) const;
  const std::string& prefix() const { return prefix_; }
  std::string path(const std::string& key) const;
  const toml::table& raw() const { return *table_; }
  ReadContext& context() { return *ctx_; }

 private:
  const toml::node* node(const std::string& key);

  const toml::table* table_;
  std::shared_ptr<ReadContext> ctx_;
  std::string prefix_;
};

/// Walks the document and records an "unknown key" error for every key not read (with the
/// nearest key the reader asked for at that place: "did you mean ..."), then throws
/// ValidationError if the context holds any error. Under a KeySchemaRecorder it records
/// the keys asked for instead and throws nothing.
void finish(const toml::table& root, ReadContext& ctx);

/// Checks for quantity(): positive, non-negative.
std::string positive(double v);
std::string non_negative(double v);

/// Describes a TOML node's value as written ("\"82\"", "82", "[...]"); strings as quote_value().
std::string describe_node(const toml::node& n);

/// A string value in quotes for a message: "82 mm", or its first 80 bytes and its length when
/// longer ("aaaa..." (200000 bytes)), so a message stays readable whatever the file holds.
std::string quote_value(const std::string& value);

}  // namespace poise::engine
