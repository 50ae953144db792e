#pragma once
/// `poise budget` in words, for the terminal: the JSON object of the checked budget
/// (budget/budget_json.h plus the Monte Carlo fields) told line by line.
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "engine/report/budget_numbers.h"

namespace poise::cli {

void print_budget_text(const nlohmann::json& j, std::ostream& out);

using engine::budget_number;
using engine::declared_text;
using engine::recomputed_text;

}  // namespace poise::cli
