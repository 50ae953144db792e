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

namespace poise::studies {

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

/// Shared state of one file's reading: file name, used keys, errors.
struct ReadContext {
  std::string file;
  std::set<std::string> used;
  std::vector<InputError> errors;
};

/// A view of one table with a dotted path prefix ("yaw.perpendicularity").
class TomlReader {
 public:
  TomlReader(const toml::table& table, std::shared_ptr<ReadContext> ctx, std::string prefix = "");

  bool has(const std::string& key) const;
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
                  const std::function<std::string(double)>& check = {},
                  std::optional<double> fallback = std::nullopt);
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

/// Walks the document and records an "unknown key" error for every key not read,
/// then throws ValidationError if the context holds any error.
void finish(const toml::table& root, ReadContext& ctx);

/// Checks for quantity(): positive, non-negative.
std::string positive(double v);
std::string non_negative(double v);

/// Describes a TOML node's value as written ("\"82\"", "82", "[...]"); strings as quote_value().
std::string describe_node(const toml::node& n);

/// A string value in quotes for a message: "82 mm", or its first 80 bytes and its length when
/// longer ("aaaa..." (200000 bytes)), so a message stays readable whatever the file holds.
std::string quote_value(const std::string& value);

}  // namespace poise::studies
