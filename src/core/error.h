#pragma once
/// Error types of Poise. User input errors carry where the bad value came from
/// (file, line, column, key), the value as written, and what was expected, so a
/// person can fix the file without reading code.
#include <stdexcept>
#include <string>

namespace poise {

/// Base of all Poise exceptions.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A command refused as given (a command-line value out of range, an --out folder that
/// already holds a run, a sample index past the run's end): nothing ran. Exit status 2,
/// like an invalid input file.
class UsageError : public Error {
 public:
  using Error::Error;
};

/// Where a value came from in an input file. line/column are 1-based; 0 = unknown.
struct SourceLocation {
  std::string file;
  int line = 0;
  int column = 0;
};

/// A value in a study or model file that is refused.
/// what() reads: "<file>:<line>:<col>: key '<key>' = <value>: expected <expected>".
class InputError : public Error {
 public:
  InputError(SourceLocation where, std::string key, std::string value, std::string expected);

  const SourceLocation& where() const { return where_; }
  const std::string& key() const { return key_; }
  const std::string& value() const { return value_; }
  const std::string& expected() const { return expected_; }

 private:
  SourceLocation where_;
  std::string key_;
  std::string value_;
  std::string expected_;
};

/// Throws poise::Error with the message if cond is false: a check of what a caller or a user
/// gave (a value out of range, a file that cannot be made), said in the caller's terms.
inline void require(bool cond, const std::string& message) {
  if (!cond) throw Error(message);
}

/// A broken internal invariant: a programming error in Poise, not a user's input. Its message
/// says so, names the invariant and where it is checked, and asks for a report, so that it is
/// never read as a mistake in the user's files.
class InvariantError : public Error {
 public:
  InvariantError(const std::string& invariant, const std::string& detail, const char* file, int line);
};

namespace detail {
[[noreturn]] void invariant_failed(const char* condition, const std::string& detail, const char* file, int line);
}  // namespace detail

}  // namespace poise

/// POISE_INVARIANT(cond, detail): checks an internal invariant (sizes that must agree, an order
/// the code itself keeps), as against require(), which checks what a caller or user gave. On
/// failure throws poise::InvariantError: "internal error (a bug in Poise ...): invariant 'cond'
/// does not hold at file:line: detail".
#define POISE_INVARIANT(cond, what)                                                    \
  do {                                                                                 \
    if (!(cond)) ::poise::detail::invariant_failed(#cond, (what), __FILE__, __LINE__); \
  } while (false)

namespace poise {}  // namespace poise
