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

/// "14.73 arcsec" or "10.47 to 16.66 arcsec" of a line, group or combined object.
std::string recomputed_text(const nlohmann::json& item, const std::string& unit);
/// The declared value as a text ("18.41 arcsec", "10.47 to 17.82 arcsec", "none").
std::string declared_text(const nlohmann::json& declared, const std::string& unit);

}  // namespace poise::cli
