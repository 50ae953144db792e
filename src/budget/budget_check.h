#pragma once
/// A budget checked line by line: every line and group recomputed from its inputs over the
/// field and set beside what its author declared, the combined figure at the lines' level and
/// at the requirement's confidence, and the likely slip behind each disagreement
/// (slip_detection.h).
///
/// Verdicts: "agrees" (every compared end within 1% of the recomputed value), "disagrees",
/// "given" (a value line: nothing to recompute), "no_declared" (nothing written to compare).
/// A declared ["least", "greatest"] is compared end by end with the recomputed range; a single
/// declared value with the recomputed greatest (a budget states its worst case).
#include <optional>
#include <string>
#include <vector>

#include "budget/budget_evaluation.h"
#include "budget/budget_file.h"

namespace poise::budget {

struct Verdict {
  std::string verdict = "no_declared";
  /// (declared - recomputed) / recomputed, of the compared end that differs most; nullopt when
  /// nothing is compared or the recomputed value is zero.
  std::optional<double> relative_difference;
  std::optional<double> relative_difference_least, relative_difference_greatest;  ///< ranged
  std::string verdict_least, verdict_greatest;  ///< ranged: the verdict of each end alone
  std::string compared;                         ///< "value", "least and greatest", "greatest"
  std::string slip;                             ///< likely slip, when one explains the disagreement
};

/// Whether every compared end of d is within 1% of r.
bool agrees(const Declared& d, const Range& r);
/// The verdict of d against r (without slip).
Verdict compare(const Declared& d, const Range& r);

struct ItemResult {
  std::string name;
  bool group = false;
  int line = 0;  ///< in the file
  bool bias = false;
  Range recomputed;  ///< budget unit's SI
  Declared declared;
  Verdict verdict;
  // lines
  std::optional<double> tolerance_sigma;  ///< SI of the tolerance
  std::string model_key;
  // groups
  std::vector<std::string> members;
  Combination combination = Combination::kRss;
  std::optional<Range> from_members_declared;
};

struct BudgetResult {
  std::vector<ItemResult> lines, groups;
  Range combined;                               ///< at the lines' level
  Range at_confidence;                          ///< random lines scaled by multiple / level
  std::optional<Range> combined_from_declared;  ///< the top items' declared values combined
  Verdict combined_verdict;
  Verdict pixels_verdict;               ///< declared_in_pixels against the combined figure
  double multiple = 1.0;                ///< two-sided normal multiple of the confidence
  double random_scale = 1.0;            ///< multiple / level
  std::optional<bool> requirement_met;  ///< at_confidence.greatest <= requirement
  std::size_t grid_points = 1;
  std::vector<double> least_at, greatest_at;  ///< field points of the combined extremes
};

/// Recomputes and checks the budget. Throws poise::Error only on a programming error; every
/// input problem was refused by load_budget.
BudgetResult check_budget(const BudgetSpec& spec);

}  // namespace poise::budget
