#include "core/error.h"

#include <utility>

namespace poise {
namespace {
std::string format(const SourceLocation& where, const std::string& key, const std::string& value,
                   const std::string& expected) {
  std::string out;
  out.append(where.file.empty() ? "<input>" : where.file);
  if (where.line > 0) {
    out.append(":").append(std::to_string(where.line));
    if (where.column > 0) out.append(":").append(std::to_string(where.column));
  }
  out.append(": key '").append(key).append("'");
  if (!value.empty()) out.append(" = ").append(value);
  out.append(": expected ").append(expected);
  return out;
}
}  // namespace

InputError::InputError(SourceLocation where, std::string key, std::string value,
                       std::string expected)
    : Error(format(where, key, value, expected)),
      where_(std::move(where)),
      key_(std::move(key)),
      value_(std::move(value)),
      expected_(std::move(expected)) {}

}  // namespace poise
