#include "budget/gain_expression.h"

#include <muParser.h>

#include <algorithm>
#include <numbers>

#include "core/error.h"

namespace poise::budget {
namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "(none: the budget has no [field])" : out;
}

}  // namespace

GainExpression::GainExpression(const std::string& text, const std::vector<std::string>& names)
    : text_(text),
      values_(std::make_unique<std::vector<double>>(names.size(), 0.0)),
      parser_(std::make_unique<mu::Parser>()) {
  try {
    if (std::find(names.begin(), names.end(), "pi") == names.end()) {
      parser_->DefineConst("pi", std::numbers::pi);
    }
    for (std::size_t i = 0; i < names.size(); ++i) parser_->DefineVar(names[i], &(*values_)[i]);
    parser_->SetExpr(text);
    // GetUsedVar parses the whole expression: syntax errors and unknown names surface here.
    // GetUsedVar lists every name the expression uses, defined or not.
    const auto& used = parser_->GetUsedVar();
    for (const auto& [name, address] : used) {
      if (std::find(names.begin(), names.end(), name) == names.end()) {
        throw Error("unknown variable '" + name + "' (the [field] defines: " + joined(names) + ")");
      }
    }
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (used.count(names[i])) used_.push_back(i);
    }
  } catch (const mu::Parser::exception_type& e) {
    if (e.GetCode() == mu::ecUNASSIGNABLE_TOKEN) {
      throw Error("unknown variable '" + e.GetToken() + "' (the [field] defines: " + joined(names) + ")");
    }
    throw Error("an expression muParser can read (" + e.GetMsg() + ")");
  }
}

GainExpression::~GainExpression() = default;
GainExpression::GainExpression(GainExpression&&) noexcept = default;
GainExpression& GainExpression::operator=(GainExpression&&) noexcept = default;

double GainExpression::evaluate(const std::vector<double>& point) const {
  POISE_INVARIANT(point.size() == values_->size(), "gain expression: wrong number of field values");
  std::copy(point.begin(), point.end(), values_->begin());
  try {
    return parser_->Eval();
  } catch (const mu::Parser::exception_type& e) {
    throw Error("expression \"" + text_ + "\" failed: " + e.GetMsg());
  }
}

}  // namespace poise::budget
