#pragma once
/// The checked budget as JSON (`poise budget --json`), every figure in the budget's unit:
///   budget {name, title, file, unit, level, combination, confidence, requirement, field}
///   lines[]   name, kind, recomputed (or recomputed_min and recomputed_max when it varies over
///             the field), value (a given line), declared (a number or [least, greatest]),
///             relative_difference ((declared - recomputed) / recomputed, the end that differs
///             most), verdict ("agrees" within 1% | "disagrees" | "given" | "no_declared"),
///             slip (the likely slip, when found), model_key, line (in the file)
///   groups[]  the same for the sub-totals, with members and combination
///   combined {least, greatest} at the lines' level, with declared, verdict, slip,
///             from_declared and where over the field the extremes are
///   at_confidence {least, greatest, confidence, multiple}
///   requirement_met (null without a requirement)
/// The command adds monte_carlo, budget_vs_monte_carlo, unmapped_model_tolerances and
/// unknown_model_keys.
#include <nlohmann/json.hpp>

#include "budget/budget_check.h"
#include "budget/budget_file.h"

namespace poise::budget {

nlohmann::json budget_json(const BudgetSpec& spec, const BudgetResult& result);

}  // namespace poise::budget
