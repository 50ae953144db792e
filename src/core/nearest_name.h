#pragma once
/// "Did you mean": the candidate nearest to a misspelled name by edit distance (insertions,
/// deletions, substitutions), or "" when none is close (more than about a third of the name's
/// letters apart). For unknown keys, kinds, outputs and model keys alike.
#include <string>
#include <vector>

namespace poise {

/// Levenshtein distance of two strings.
std::size_t edit_distance(const std::string& a, const std::string& b);

/// The nearest of `candidates` to `name`, or "" if none is within max(2, |name| / 3).
std::string nearest_name(const std::string& name, const std::vector<std::string>& candidates);

/// "; did you mean 'X'?" for the nearest candidate, or "" when none is close.
std::string did_you_mean(const std::string& name, const std::vector<std::string>& candidates);

}  // namespace poise
