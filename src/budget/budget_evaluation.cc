#include "budget/budget_evaluation.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/units.h"
#include "sampling/distribution.h"

namespace poise::budget {

bool Range::varies() const { return greatest - least > 1e-12 * std::max(std::abs(least), std::abs(greatest)); }

double confidence_multiple(double p) {
  require(p > 0.0 && p < 1.0, "confidence must be in (0, 1)");
  return sampling::standard_normal_quantile(0.5 * (1.0 + p));
}

double combine(Combination rule, const std::vector<std::pair<double, bool>>& entries) {
  double linear = 0.0, squares = 0.0, bias = 0.0, random_squares = 0.0;
  for (const auto& [v, is_bias] : entries) {
    linear += v;
    squares += v * v;
    (is_bias ? bias : random_squares) += is_bias ? v : v * v;
  }
  switch (rule) {
    case Combination::kRss: return std::sqrt(squares);
    case Combination::kLinear: return linear;
    case Combination::kBiasLinearRandomRss: return bias + std::sqrt(random_squares);
  }
  return NAN;
}

double tolerance_sigma(const LineSpec& line) {
  if (line.given) return 0.0;
  if (line.distribution == sampling::DistributionKind::kFixed) return line.tolerance;
  return sampling::Distribution(line.distribution, 0.0, line.tolerance, line.convention).stddev();
}

double line_base(const LineSpec& line, int level) {
  if (line.given) return line.value;
  const bool fixed = line.distribution == sampling::DistributionKind::kFixed;
  const double at_level = fixed ? line.tolerance : level * tolerance_sigma(line);
  return line.lever ? at_level / *line.lever : at_level;
}

namespace {
std::vector<std::string> names_of(const std::vector<FieldVariable>& field) {
  std::vector<std::string> out;
  out.reserve(field.size());
  for (const auto& v : field) out.push_back(v.name);
  return out;
}
std::string describe_point(const std::vector<FieldVariable>& field, const std::vector<double>& x) {
  std::string out;
  for (std::size_t k = 0; k < field.size(); ++k) {
    std::string v;
    try {
      v = field[k].unit.empty() ? units::format(x[k], "", 6) : units::format(x[k], field[k].unit, 6);
    } catch (const Error&) {
      v = std::to_string(x[k]);
    }
    out += (out.empty() ? "" : ", ") + field[k].name + " = " + v;
  }
  return out;
}
}  // namespace

std::vector<InputError> check_expressions(const BudgetSpec& spec) {
  std::vector<InputError> errors;
  const std::vector<std::string> names = names_of(spec.field);
  const FieldGrid grid(spec.field, spec.field_points);
  auto check = [&](const std::string& text, const std::string& path, int line) {
    if (text.empty()) return;
    const GainExpression e(text, names);
    std::vector<double> x;
    for (std::size_t i = 0; i < grid.size(); ++i) {
      grid.point(i, x);
      std::string problem;
      try {
        const double v = e.evaluate(x);
        if (!std::isfinite(v)) problem = "not finite";
      } catch (const Error& err) {
        problem = err.what();
      }
      if (!problem.empty()) {
        errors.emplace_back(
            SourceLocation{spec.file, line, 0}, path, "\"" + text + "\"",
            "a finite value over the whole field (" + problem + " at " + describe_point(spec.field, x) + ")");
        return;
      }
    }
  };
  for (const auto& l : spec.lines) {
    if (!l.given) check(l.gain, l.path + ".gain", l.gain_line ? l.gain_line : l.line);
    check(l.propagation, l.path + ".propagation", l.propagation_line ? l.propagation_line : l.line);
  }
  for (const auto& g : spec.groups) {
    check(g.propagation, g.path + ".propagation", g.propagation_line ? g.propagation_line : g.line);
  }
  return errors;
}

BudgetEvaluator::BudgetEvaluator(const BudgetSpec& spec)
    : spec_(spec), grid_(spec.field, spec.field_points), field_names_(names_of(spec.field)) {
  const std::size_t n_lines = spec.lines.size();
  members_.resize(items());
  propagations_.resize(items());
  for (std::size_t i = 0; i < n_lines; ++i) {
    const LineSpec& l = spec.lines[i];
    gains_.emplace_back(l.given ? "1" : l.gain, field_names_);
    bases_.push_back(line_base(l, spec.level));
    if (!l.propagation.empty()) propagations_[i].emplace(l.propagation, field_names_);
  }
  std::vector<bool> in_group(items(), false);
  for (std::size_t g = 0; g < spec.groups.size(); ++g) {
    const GroupSpec& gs = spec.groups[g];
    if (!gs.propagation.empty()) propagations_[n_lines + g].emplace(gs.propagation, field_names_);
    for (const auto& m : gs.members) {
      for (std::size_t k = 0; k < items(); ++k) {
        if (name(k) == m) {
          members_[n_lines + g].push_back(k);
          in_group[k] = true;
        }
      }
    }
  }
  std::vector<std::pair<int, std::size_t>> order;
  for (std::size_t k = 0; k < items(); ++k) {
    if (!in_group[k]) order.emplace_back(is_group(k) ? spec.groups[k - n_lines].line : spec.lines[k].line, k);
  }
  std::stable_sort(order.begin(), order.end());
  for (const auto& [line, k] : order) top_.push_back(k);
}

const std::string& BudgetEvaluator::name(std::size_t item) const {
  return is_group(item) ? spec_.groups[item - spec_.lines.size()].name : spec_.lines[item].name;
}

const Declared& BudgetEvaluator::declared(std::size_t item) const {
  return is_group(item) ? spec_.groups[item - spec_.lines.size()].declared : spec_.lines[item].declared;
}

bool BudgetEvaluator::is_bias(std::size_t item) const {
  if (!is_group(item)) return spec_.lines[item].kind == LineKind::kBias;
  const auto& m = members_[item];
  return !m.empty() && std::all_of(m.begin(), m.end(), [&](std::size_t k) { return is_bias(k); });
}

double BudgetEvaluator::node_value(const std::vector<std::size_t>& entries, Combination rule,
                                   const std::vector<double>& x, const Mode& mode) const {
  std::vector<std::pair<double, bool>> e;
  e.reserve(entries.size());
  for (std::size_t k : entries) {
    if (mode.left_out && *mode.left_out == k) continue;
    double v = value(k, x, mode, false);
    if (mode.use_propagation && propagations_[k]) v *= std::abs(propagations_[k]->evaluate(x));
    e.emplace_back(v, is_bias(k));
  }
  return combine(rule, e);
}

double BudgetEvaluator::value(std::size_t item, const std::vector<double>& x, const Mode& mode, bool top_call) const {
  if (!top_call && mode.declared != Mode::Declared::kNo) {
    const Declared& d = declared(item);
    if (d.present) return mode.declared == Mode::Declared::kLeast ? d.least : d.greatest;
  }
  if (!is_group(item)) {
    const LineSpec& l = spec_.lines[item];
    const double scale = l.kind == LineKind::kRandom ? mode.random_scale : 1.0;
    return std::abs(bases_[item] * gains_[item].evaluate(x)) * scale;
  }
  const GroupSpec& g = spec_.groups[item - spec_.lines.size()];
  // rule and left_out speak of the evaluated node's own entries, not of deeper groups.
  Mode inner = mode;
  inner.rule.reset();
  if (!top_call) inner.left_out.reset();
  const Combination rule = top_call && mode.rule ? *mode.rule : g.combination;
  return node_value(members_[item], rule, x, inner);
}

Range BudgetEvaluator::item_range(std::size_t item, const Mode& mode) const {
  Range r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  std::vector<double> x;
  for (std::size_t i = 0; i < grid_.size(); ++i) {
    grid_.point(i, x);
    const double v = value(item, x, mode, true);
    r.least = std::min(r.least, v);
    r.greatest = std::max(r.greatest, v);
  }
  return r;
}

Range BudgetEvaluator::combined_range(const Mode& mode, std::vector<double>* least_at,
                                      std::vector<double>* greatest_at) const {
  Range r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  std::vector<double> x;
  Mode inner = mode;
  inner.rule.reset();
  for (std::size_t i = 0; i < grid_.size(); ++i) {
    grid_.point(i, x);
    // The combined figure's entries: the top items, each with its own declared value in a
    // declared pass (the combined figure is the node being evaluated).
    std::vector<std::pair<double, bool>> e;
    for (std::size_t k : top_) {
      if (mode.left_out && *mode.left_out == k) continue;
      double v = value(k, x, inner, false);
      if (mode.use_propagation && propagations_[k]) v *= std::abs(propagations_[k]->evaluate(x));
      e.emplace_back(v, is_bias(k));
    }
    const double v = combine(mode.rule.value_or(spec_.combination), e);
    if (v < r.least) {
      r.least = v;
      if (least_at) *least_at = x;
    }
    if (v > r.greatest) {
      r.greatest = v;
      if (greatest_at) *greatest_at = x;
    }
  }
  return r;
}

Range BudgetEvaluator::line_range_as(const LineSpec& variant, const std::vector<double>* point_scale) const {
  const GainExpression gain(variant.given ? "1" : variant.gain, field_names_);
  const double base = line_base(variant, spec_.level);
  Range r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  std::vector<double> x;
  for (std::size_t i = 0; i < grid_.size(); ++i) {
    grid_.point(i, x);
    if (point_scale) {
      for (std::size_t k = 0; k < x.size(); ++k) x[k] *= (*point_scale)[k];
    }
    const double v = std::abs(base * gain.evaluate(x));
    r.least = std::min(r.least, v);
    r.greatest = std::max(r.greatest, v);
  }
  return r;
}

}  // namespace poise::budget
