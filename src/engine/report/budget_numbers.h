#pragma once
/// Figures of a checked budget in words, shared by its report page and the terminal text of
/// `poise budget`: the JSON objects of budget/budget_json.h told with 4 significant digits.
#include <string>

#include <nlohmann/json.hpp>

namespace poise::engine {

/// A figure with 4 significant digits ("14.73", "0.004432"); "-" for null.
std::string budget_number(const nlohmann::json& v);

/// "4.2 arcsec" or "3.5 to 6.1 arcsec" of a line, group or combined object.
std::string recomputed_text(const nlohmann::json& item, const std::string& unit);
/// The declared value as a text ("4.3 arcsec", "3.5 to 6.2 arcsec", "none").
std::string declared_text(const nlohmann::json& declared, const std::string& unit);

}  // namespace poise::engine
