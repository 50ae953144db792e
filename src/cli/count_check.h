#pragma once
/// A command-line check of a count (samples, base rows): a whole number of at least 1, with a
/// message that says so (CLI11's PositiveNumber prints the range of a double instead).
#include <CLI/CLI.hpp>
#include <string>

namespace poise::cli {

inline CLI::Validator at_least_one() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        if (digits && text.find_first_not_of('0') != std::string::npos) return "";
        std::string shown = text.size() > 40 ? text.substr(0, 40) + "..." : text;
        return "must be a whole number of at least 1, got \"" + shown + "\"";
      },
      "INT>=1");
}

}  // namespace poise::cli
