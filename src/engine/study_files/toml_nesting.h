#pragma once
/// The nesting depth of a TOML text, measured before toml++ parses it: toml++ descends
/// recursively, so 50,000 levels of dotted keys or table headers overflow the stack. A cheap
/// scan of the text finds the first place deeper than a limit (kMaxTomlNesting), counting
/// together the levels of the current table header ([a.b.c] is 3), of a dotted key (a.b.c = is
/// 3) and of open arrays and inline tables; strings and comments are skipped.
#include <optional>
#include <string_view>

namespace poise::engine {

/// Deepest nesting a study, model or other TOML input may have (tables, dotted keys, arrays
/// and inline tables together). Real files need fewer than 10.
inline constexpr int kMaxTomlNesting = 64;

struct NestingPlace {
  int line = 0;    ///< 1-based
  int column = 0;  ///< 1-based
};

/// The first place where `text` nests deeper than `limit` levels, if any.
std::optional<NestingPlace> find_too_deep_nesting(std::string_view text, int limit = kMaxTomlNesting);

}  // namespace poise::engine
