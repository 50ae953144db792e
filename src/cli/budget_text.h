#pragma once
/// `poise budget` in words, for the terminal: the JSON object of the checked budget
/// (budget/budget_json.h plus the Monte Carlo fields) told line by line.
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

namespace poise::cli {

void print_budget_text(const nlohmann::json& j, std::ostream& out);

/// A figure with 4 significant digits ("14.73", "0.004432"); "-" for null.
std::string budget_number(const nlohmann::json& v);

/// "4.2 arcsec" or "3.5 to 6.1 arcsec" of a line, group or combined object.
std::string recomputed_text(const nlohmann::json& item, const std::string& unit);
/// The declared value as a text ("4.3 arcsec", "3.5 to 6.2 arcsec", "none").
std::string declared_text(const nlohmann::json& declared, const std::string& unit);

}  // namespace poise::cli
