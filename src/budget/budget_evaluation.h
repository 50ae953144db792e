#pragma once
/// Recomputation of a budget from its inputs, point by point of the field grid.
///
/// A tolerance line's contribution at a field point x, in the budget's level:
///     c = k_level * sigma(tolerance; distribution, tolerance_is) / lever * gain(x)
/// (no lever: the tolerance is already in the budget's unit; a "fixed" bias: c = t / lever *
/// gain, a value that does not scale with the level). A value line's c is its value.
/// An item (line or group) enters its group, or the combined figure, as |c| * |propagation(x)|.
/// Combination of the entries e_i of a group or of the budget:
///     rss                       sqrt(sum e_i^2)
///     linear                    sum e_i
///     bias_linear_random_rss    sum over bias e_i + sqrt(sum over random e_i^2)
/// (a group counts as a bias when all its members are biases). At the requirement's
/// confidence p, every random line is scaled by m / k_level, m = Phi^-1((1 + p) / 2), the
/// two-sided normal multiple (0.9973 -> 3.000); biases are not scaled.
#include <optional>
#include <string>
#include <vector>

#include "budget/budget_file.h"
#include "budget/field_grid.h"
#include "budget/gain_expression.h"
#include "core/error.h"

namespace poise::budget {

/// Least and greatest over the field (SI of the budget's unit).
struct Range {
  double least = 0.0, greatest = 0.0;
  bool varies() const;
};

/// How an item is valued in one pass over the grid.
struct Mode {
  /// Items with a declared value take it (least or greatest end) instead of being recomputed;
  /// `declared_below` applies this to the members below the evaluated item only.
  enum class Declared { kNo, kLeast, kGreatest } declared = Declared::kNo;
  double random_scale = 1.0;  ///< factor on random lines (the confidence multiple / level)
  bool use_propagation = true;
  std::optional<std::size_t> left_out;  ///< an item taken as zero
  std::optional<Combination> rule;      ///< replaces the combination of the evaluated node
};

/// Two-sided normal multiple of a confidence: Phi^-1((1 + p) / 2).
double confidence_multiple(double p);

/// Combines entries (value, is_bias) by a rule.
double combine(Combination rule, const std::vector<std::pair<double, bool>>& entries);

/// Standard deviation of a line's tolerance (SI of the tolerance), model-file conventions;
/// a "fixed" tolerance is its own value.
double tolerance_sigma(const LineSpec& line);

/// The line's contribution per unit gain: k_level * sigma / lever (or the value).
double line_base(const LineSpec& line, int level);

/// Every gain and propagation evaluated over the whole grid: an error (file, line, key) for
/// each that is not finite somewhere ("1/cos(pitch)" at pitch = 90 deg), or fails to evaluate.
std::vector<InputError> check_expressions(const BudgetSpec& spec);

/// The compiled budget: items 0..lines-1 are the lines, then the groups.
class BudgetEvaluator {
 public:
  explicit BudgetEvaluator(const BudgetSpec& spec);

  const BudgetSpec& spec() const { return spec_; }
  const FieldGrid& grid() const { return grid_; }
  std::size_t items() const { return spec_.lines.size() + spec_.groups.size(); }
  bool is_group(std::size_t item) const { return item >= spec_.lines.size(); }
  const std::string& name(std::size_t item) const;
  const Declared& declared(std::size_t item) const;
  bool is_bias(std::size_t item) const;
  /// Members of a group item (item indices); empty for a line.
  const std::vector<std::size_t>& members(std::size_t item) const { return members_[item]; }
  /// Items of the combined figure (not in any group), in file order.
  const std::vector<std::size_t>& top() const { return top_; }

  /// Range over the grid of an item's own value (its gain included, its propagation not).
  Range item_range(std::size_t item, const Mode& mode) const;
  /// Range over the grid of the combined figure.
  Range combined_range(const Mode& mode, std::vector<double>* least_at = nullptr,
                       std::vector<double>* greatest_at = nullptr) const;
  /// Range of a line recomputed with other inputs (same name and place): for slip checks.
  Range line_range_as(const LineSpec& variant, const std::vector<double>* point_scale = nullptr) const;

 private:
  double value(std::size_t item, const std::vector<double>& x, const Mode& mode, bool top_call) const;
  double node_value(const std::vector<std::size_t>& entries, Combination rule, const std::vector<double>& x,
                    const Mode& mode) const;

  const BudgetSpec& spec_;
  FieldGrid grid_;
  std::vector<std::string> field_names_;
  std::vector<GainExpression> gains_;                        // per line
  std::vector<std::optional<GainExpression>> propagations_;  // per item
  std::vector<double> bases_;                                // per line
  std::vector<std::vector<std::size_t>> members_;
  std::vector<std::size_t> top_;
};

}  // namespace poise::budget
