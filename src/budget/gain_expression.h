#pragma once
/// A gain or propagation factor of a budget line: a number or an expression of the [field]
/// variables ("1/cos(pitch)", "sqrt((tan(pitch)*sin(yaw))^2 + cos(yaw)^2)"), parsed and
/// evaluated by muParser (libmuparser-dev), not by a parser of our own. Angles reach the
/// expression in radians, as muParser's sin/cos/tan expect; `pi` is defined.
#include <memory>
#include <string>
#include <vector>

namespace mu {
class Parser;
}

namespace poise::budget {

/// Not thread-safe: evaluate() writes the point into the variables muParser reads.
class GainExpression {
 public:
  /// Compiles `text` over the variables `names` (values passed to evaluate() in that order).
  /// Throws poise::Error whose message says what is wrong: "unknown variable 'x' (the
  /// [field] defines: pitch, yaw)", or the parser's message with the position.
  GainExpression(const std::string& text, const std::vector<std::string>& names);
  ~GainExpression();
  GainExpression(GainExpression&&) noexcept;
  GainExpression& operator=(GainExpression&&) noexcept;

  /// Value at a point of the field (SI values, one per name). Throws poise::Error if the
  /// parser fails at run time (e.g. a division by zero it reports).
  double evaluate(const std::vector<double>& point) const;
  /// Whether the expression uses any variable (else it is one number over the whole field).
  bool uses_variables() const { return !used_.empty(); }
  /// Indices (into names) of the variables it uses.
  const std::vector<std::size_t>& used() const { return used_; }
  const std::string& text() const { return text_; }

 private:
  std::string text_;
  std::unique_ptr<std::vector<double>> values_;  // stable addresses for muParser's DefineVar
  std::unique_ptr<mu::Parser> parser_;
  std::vector<std::size_t> used_;
};

}  // namespace poise::budget
