#pragma once
// Helpers of the budget tests: a budget file from text, an item of a result by name.
#include <stdexcept>
#include <string>

#include "budget/budget_check.h"
#include "budget/budget_file.h"
#include "core/units.h"
#include "test_util.h"

namespace poise::test {

inline constexpr double kArcsec = 1.0 / units::kArcsecPerRad;

inline budget::BudgetSpec load_text(const TempDir& dir, const std::string& text) {
  const std::string path = dir.file("budget.toml");
  write_text(path, text);
  return budget::load_budget(path);
}

/// The line or group of that name.
inline const budget::ItemResult& line(const budget::BudgetResult& r, const std::string& name) {
  for (const auto& l : r.lines) {
    if (l.name == name) return l;
  }
  for (const auto& g : r.groups) {
    if (g.name == name) return g;
  }
  throw std::runtime_error("no line or group " + name);
}

/// A [budget] table in arcsec at 1 sigma with this rule, confidence 0.9973, and extra keys.
inline std::string head(const std::string& combination, const std::string& extra = "") {
  return "[budget]\nname = \"t\"\nunit = \"arcsec\"\nlevel = \"1sigma\"\ncombination = \"" + combination +
         "\"\nconfidence = 0.9973\n" + extra + "\n";
}

/// The first line of a one-line budget with these extra [budget] keys (or [field]).
inline budget::ItemResult one_line(const std::string& body, const std::string& extra = "") {
  TempDir dir;
  const budget::BudgetResult r = budget::check_budget(load_text(dir, head("rss", extra) + body));
  return r.lines.front();
}

}  // namespace poise::test
