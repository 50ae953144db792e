#pragma once
/// Internal to load_budget (budget_file.cc): reading one [[line]] or [[group]] and the checks
/// across them. Errors are recorded in the reader's context, never thrown.
#include <optional>
#include <string>
#include <vector>

#include "budget/budget_file.h"
#include "engine/study_files/toml_reader.h"

namespace poise::budget {

/// The budget's unit, and the pixel IFOV when pixels may be written.
struct Units {
  units::Dimension dimension;
  std::string unit;
  std::optional<double> pixel;
};

Combination parse_combination(engine::TomlReader& t, const std::string& key, std::optional<Combination> fallback);

/// A value of the budget's dimension (or px, when allow_pixels and an IFOV is given), in SI.
/// Records an error and returns nullopt when it does not parse.
std::optional<double> read_value(engine::TomlReader& t, const std::string& key, const Units& u, bool allow_pixels);

/// `declared` as "x" or ["least", "greatest"]; absent: present = false.
Declared read_declared(engine::TomlReader& t, const std::string& key, const Units& u);

LineSpec read_line(engine::TomlReader& t, const Units& u, const std::vector<std::string>& field_names);
GroupSpec read_group(engine::TomlReader& t, const Units& u, const std::vector<std::string>& field_names,
                     Combination fallback);

/// Unique names, existing members, no item in two groups, no cycle.
void check_structure(const BudgetSpec& b, engine::ReadContext& ctx);

}  // namespace poise::budget
