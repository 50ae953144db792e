#include "core/error.h"

#include <utility>

namespace poise {
namespace {
// A key or value as echoed in a message: whole up to a screen line's worth, else its start
// and its length (a 3 MB value must not become a 3 MB message).
std::string bounded(const std::string& text, std::size_t limit) {
  if (text.size() <= limit) return text;
  std::size_t cut = limit > 400 ? limit / 2 : 80;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;  // whole UTF-8 characters
  return text.substr(0, cut) + "... (" + std::to_string(text.size()) + " bytes)";
}

std::string format(const SourceLocation& where, const std::string& key, const std::string& value,
                   const std::string& expected) {
  std::string out;
  out.append(where.file.empty() ? "<input>" : where.file);
  if (where.line > 0) {
    out.append(":").append(std::to_string(where.line));
    if (where.column > 0) out.append(":").append(std::to_string(where.column));
  }
  out.append(": key '").append(bounded(key, 120)).append("'");
  if (!value.empty()) out.append(" = ").append(bounded(value, 200));
  // What was expected may quote the value again ("unknown unit \"...\""): bounded too.
  out.append(": expected ").append(bounded(expected, 600));
  return out;
}
}  // namespace

InputError::InputError(SourceLocation where, std::string key, std::string value, std::string expected)
    : Error(format(where, key, value, expected)),
      where_(std::move(where)),
      key_(std::move(key)),
      value_(std::move(value)),
      expected_(std::move(expected)) {}

InvariantError::InvariantError(const std::string& invariant, const std::string& detail, const char* file, int line)
    : Error(
          "internal error (a bug in Poise, not in your files; please report it with the command and its files): "
          "invariant '" +
          invariant + "' does not hold at " + file + ":" + std::to_string(line) +
          (detail.empty() ? std::string() : ": " + detail)) {}

namespace detail {
void invariant_failed(const char* condition, const std::string& detail, const char* file, int line) {
  throw InvariantError(condition, detail, file, line);
}
}  // namespace detail

}  // namespace poise
