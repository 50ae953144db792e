#include "kinds/formula/unit_formula.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <optional>

#include "core/nearest_name.h"

namespace poise::kinds::formula {
namespace {
using units::Dimension;

// How a function's dimensions combine.
enum class Rule {
  kTrig,     // angle or number -> number
  kInverse,  // number -> angle
  kAtan2,    // (y, x) of one dimension -> angle
  kNumber,   // number -> number
  kSqrt,     // exponents halved
  kSame,     // one argument, same dimension
  kSign,     // any -> number
  kAllSame,  // every argument one dimension -> that dimension
  kPower,    // pow(x, y): as x^y
};

struct Function {
  const char* name;
  const char* muparser;  // its name for muParser
  Rule rule;
  std::size_t min_args, max_args;
};

constexpr std::size_t kMany = 64;
constexpr Function kFunctions[] = {
    {"sin", "sin", Rule::kTrig, 1, 1},        {"cos", "cos", Rule::kTrig, 1, 1},
    {"tan", "tan", Rule::kTrig, 1, 1},        {"asin", "asin", Rule::kInverse, 1, 1},
    {"acos", "acos", Rule::kInverse, 1, 1},   {"atan", "atan", Rule::kInverse, 1, 1},
    {"atan2", "atan2", Rule::kAtan2, 2, 2},   {"sinh", "sinh", Rule::kNumber, 1, 1},
    {"cosh", "cosh", Rule::kNumber, 1, 1},    {"tanh", "tanh", Rule::kNumber, 1, 1},
    {"asinh", "asinh", Rule::kNumber, 1, 1},  {"acosh", "acosh", Rule::kNumber, 1, 1},
    {"atanh", "atanh", Rule::kNumber, 1, 1},  {"exp", "exp", Rule::kNumber, 1, 1},
    {"ln", "ln", Rule::kNumber, 1, 1},        {"log", "ln", Rule::kNumber, 1, 1},
    {"log10", "log10", Rule::kNumber, 1, 1},  {"log2", "log2", Rule::kNumber, 1, 1},
    {"sqrt", "sqrt", Rule::kSqrt, 1, 1},      {"abs", "abs", Rule::kSame, 1, 1},
    {"rint", "rint", Rule::kSame, 1, 1},      {"floor", "floor", Rule::kSame, 1, 1},
    {"ceil", "ceil", Rule::kSame, 1, 1},      {"sign", "sign", Rule::kSign, 1, 1},
    {"min", "min", Rule::kAllSame, 1, kMany}, {"max", "max", Rule::kAllSame, 1, kMany},
    {"sum", "sum", Rule::kAllSame, 1, kMany}, {"avg", "avg", Rule::kAllSame, 1, kMany},
    {"hypot", "hypot", Rule::kAllSame, 2, 2}, {"pow", "pow", Rule::kPower, 2, 2},
};

const Function* find_function(const std::string& name) {
  for (const Function& f : kFunctions) {
    if (name == f.name) return &f;
  }
  return nullptr;
}

std::string number_text(double x) {
  char buf[40];
  const auto res = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, res.ptr);
}

// A checked subtree: its muParser text, dimension, and what the rules need of it.
struct Term {
  std::string text;
  Dimension dim;
  std::optional<double> constant;  // its value, when it uses no name
  bool zero = false;               // a bare 0, which takes any dimension
};

class Checker {
 public:
  Checker(const std::string& text, const std::map<std::string, Dimension>& names) : s_(text), names_(names) {}

  CheckedFormula run() {
    skip_space();
    if (pos_ >= s_.size()) throw FormulaError(0, "empty formula");
    Term t = ternary();
    skip_space();
    if (pos_ < s_.size()) throw FormulaError(pos_, "unexpected '" + std::string(1, s_[pos_]) + "'");
    return {t.dim, t.text, used_};
  }

 private:
  void skip_space() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  bool accept(const std::string& op) {
    skip_space();
    if (s_.compare(pos_, op.size(), op) != 0) return false;
    pos_ += op.size();
    return true;
  }
  void expect(const std::string& op, const std::string& what) {
    if (!accept(op)) {
      throw FormulaError(pos_,
                         "expected '" + op + "' " + what +
                             (pos_ < s_.size() ? ", found '" + std::string(1, s_[pos_]) + "'" : ", found the end"));
    }
  }

  // Two operands that must share a dimension (a bare 0 takes the other's).
  Dimension join(const Term& a, const Term& b, std::size_t at, const std::string& op) const {
    if (a.zero) return b.dim;
    if (b.zero || a.dim == b.dim) return a.dim;
    throw FormulaError(at, "'" + op + "' joins " + dimension_words(a.dim) + " and " + dimension_words(b.dim));
  }

  Term ternary() {
    Term c = logical_or();
    skip_space();
    const std::size_t at = pos_;
    if (!accept("?")) return c;
    need_number(c, at, "the condition of ?:");
    Term a = ternary();
    expect(":", "after the first branch of ?:");
    const std::size_t at_b = pos_;
    Term b = ternary();
    Term t{"(" + c.text + "?" + a.text + ":" + b.text + ")", join(a, b, at_b, "?:"), std::nullopt, a.zero && b.zero};
    return t;
  }
  // a || b and a && b: operands of no unit, left to right; && binds tighter.
  Term logical_or() { return logical("||", &Checker::logical_and); }
  Term logical_and() { return logical("&&", &Checker::comparison); }
  Term logical(const std::string& op, Term (Checker::*operand)()) {
    Term a = (this->*operand)();
    for (;;) {
      skip_space();
      const std::size_t at = pos_;
      if (!accept(op)) return a;
      Term b = (this->*operand)();
      need_number(a, at, "'" + op + "'");
      need_number(b, at, "'" + op + "'");
      a = {"(" + a.text + op + b.text + ")", {}, std::nullopt, false};
    }
  }
  Term comparison() {
    Term a = additive();
    skip_space();
    const std::size_t at = pos_;
    for (const char* op : {"<=", ">=", "==", "!=", "<", ">"}) {
      if (!accept(op)) continue;
      Term b = additive();
      join(a, b, at, op);
      return {"(" + a.text + op + b.text + ")", {}, std::nullopt, false};
    }
    return a;
  }
  Term additive() {
    Term a = multiplicative();
    for (;;) {
      skip_space();
      const std::size_t at = pos_;
      if (pos_ >= s_.size() || (s_[pos_] != '+' && s_[pos_] != '-')) return a;
      const char op = s_[pos_++];
      Term b = multiplicative();
      const Dimension d = join(a, b, at, std::string(1, op));
      std::optional<double> c;
      if (a.constant && b.constant) c = op == '+' ? *a.constant + *b.constant : *a.constant - *b.constant;
      a = {"(" + a.text + op + b.text + ")", d, c, false};
    }
  }
  Term multiplicative() {
    Term a = unary();
    for (;;) {
      skip_space();
      if (pos_ >= s_.size() || (s_[pos_] != '*' && s_[pos_] != '/')) return a;
      const char op = s_[pos_++];
      Term b = unary();
      Dimension d;
      for (std::size_t k = 0; k < d.e.size(); ++k) {
        d.e[k] = static_cast<std::int8_t>(op == '*' ? a.dim.e[k] + b.dim.e[k] : a.dim.e[k] - b.dim.e[k]);
      }
      std::optional<double> c;
      if (a.constant && b.constant) c = op == '*' ? *a.constant * *b.constant : *a.constant / *b.constant;
      a = {"(" + a.text + op + b.text + ")", d, c, a.zero};
    }
  }
  Term unary() {
    skip_space();
    if (accept("-")) {
      Term a = unary();
      return {"(-" + a.text + ")", a.dim, a.constant ? std::optional<double>(-*a.constant) : std::nullopt, a.zero};
    }
    if (accept("+")) return unary();
    return power();
  }
  Term power() {
    Term a = primary();
    skip_space();
    const std::size_t at = pos_;
    if (!accept("^")) return a;
    Term b = unary();  // right-associative: a^b^c = a^(b^c); a^-1 allowed
    std::optional<double> c;
    if (a.constant && b.constant) c = std::pow(*a.constant, *b.constant);
    return {"(" + a.text + "^" + b.text + ")", power_dimension(a, b, at), c, false};
  }
  // The dimension of a^b: b a number, a constant one unless a is a number, and the powers
  // of a's units whole.
  Dimension power_dimension(const Term& a, const Term& b, std::size_t at) const {
    need_number(b, at, "an exponent");
    Dimension d;
    if (a.dim == Dimension{}) return d;
    if (!b.constant) throw FormulaError(at, "the exponent of " + dimension_words(a.dim) + " must be a constant number");
    for (std::size_t k = 0; k < d.e.size(); ++k) {
      const double e = a.dim.e[k] * *b.constant;
      if (std::abs(e - std::round(e)) > 1e-9) {
        throw FormulaError(at, "the power " + number_text(*b.constant) + " of " + dimension_words(a.dim) +
                                   " gives a fractional power of a unit");
      }
      d.e[k] = static_cast<std::int8_t>(std::lround(e));
    }
    return d;
  }
  void need_number(const Term& t, std::size_t at, const std::string& what) const {
    if (!(t.dim == Dimension{}) && !t.zero) {
      throw FormulaError(at, what + " must be a plain number, not " + dimension_words(t.dim));
    }
  }

  Term primary() {
    skip_space();
    if (pos_ >= s_.size()) throw FormulaError(pos_, "the formula ends where a value is expected");
    const char ch = s_[pos_];
    if (ch == '(') {
      ++pos_;
      Term t = ternary();
      expect(")", "to close the '('");
      return t;
    }
    if (std::isdigit(static_cast<unsigned char>(ch)) || ch == '.') return number();
    if (std::isalpha(static_cast<unsigned char>(ch)) || ch == '_') return name();
    throw FormulaError(pos_, "unexpected '" + std::string(1, ch) + "' where a value is expected");
  }

  std::string identifier() {
    const std::size_t start = pos_;
    while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_')) ++pos_;
    return s_.substr(start, pos_ - start);
  }

  Term number() {
    const std::size_t start = pos_;
    double x = 0.0;
    const auto res = std::from_chars(s_.data() + pos_, s_.data() + s_.size(), x);
    if (res.ec != std::errc()) throw FormulaError(pos_, "not a number");
    pos_ = static_cast<std::size_t>(res.ptr - s_.data());
    const std::string unit = unit_after_number();
    if (unit.empty()) return {number_text(x), {}, x, x == 0.0};
    units::Quantity q;
    try {
      q = units::parse_quantity(number_text(x) + " " + unit);
    } catch (const Error& e) {
      throw FormulaError(start, e.what());
    }
    return {"(" + number_text(q.value) + ")", q.dim, q.value, false};
  }

  // The unit written after a number: a unit word right after it ("23 mm", "2 s": a number
  // followed by a word is a constant with its unit, never a product), then more unit words
  // joined by * or / with no space around them, each with an optional ^n ("9.81 m/s^2",
  // "1 N*m"). A spaced operator ends the unit: "2 mm * x".
  std::string unit_after_number() {
    std::size_t p = pos_;
    while (p < s_.size() && s_[p] == ' ') ++p;
    std::string unit;
    for (bool first = true;; first = false) {
      std::size_t q = p;
      std::string joiner;
      if (!first) {
        if (q >= s_.size() || (s_[q] != '*' && s_[q] != '/')) break;
        joiner = std::string(1, s_[q++]);
      }
      const std::size_t word_start = q;
      while (q < s_.size() && (std::isalpha(static_cast<unsigned char>(s_[q])) || s_[q] == '_')) ++q;
      const std::string word = s_.substr(word_start, q - word_start);
      if (word.empty() || !is_unit(word) || (q < s_.size() && s_[q] == '(')) break;
      std::string power;
      if (q < s_.size() && s_[q] == '^') {
        std::size_t r = q + 1;
        if (r < s_.size() && s_[r] == '-') ++r;
        const std::size_t digits = r;
        while (r < s_.size() && std::isdigit(static_cast<unsigned char>(s_[r]))) ++r;
        if (r > digits) {
          power = s_.substr(q, r - q);
          q = r;
        }
      }
      unit += joiner + word + power;
      p = q;
      pos_ = q;
    }
    return unit;
  }

  static bool is_unit(const std::string& word) {
    try {
      units::parse_quantity("1 " + word);
      return true;
    } catch (const Error&) {
      return false;
    }
  }

  Term name() {
    const std::size_t at = pos_;
    const std::string id = identifier();
    skip_space();
    if (pos_ < s_.size() && s_[pos_] == '(') return call(id, at);
    if (id == "pi") return {"pi", {}, units::kPi, false};  // muParser's own _pi is 3.141592653589
    const auto it = names_.find(id);
    if (it == names_.end()) {
      std::vector<std::string> known;
      for (const auto& [n, d] : names_) known.push_back(n);
      std::string message = "unknown name '" + id + "'" + did_you_mean(id, known);
      if (find_function(id)) message = "'" + id + "' is a function: call it as " + id + "(...)";
      throw FormulaError(at, message);
    }
    if (std::find(used_.begin(), used_.end(), id) == used_.end()) used_.push_back(id);
    return {id, it->second, std::nullopt, false};
  }

  Term call(const std::string& id, std::size_t at) {
    const Function* f = find_function(id);
    if (!f) {
      std::vector<std::string> known;
      for (const Function& g : kFunctions) known.emplace_back(g.name);
      throw FormulaError(at, "unknown function '" + id + "'" + did_you_mean(id, known));
    }
    expect("(", "after " + id);
    std::vector<Term> args;
    std::vector<std::size_t> where;
    skip_space();
    if (!accept(")")) {
      do {
        skip_space();
        where.push_back(pos_);
        args.push_back(ternary());
      } while (accept(","));
      expect(")", "to close " + id + "(");
    }
    if (args.size() < f->min_args || args.size() > f->max_args) {
      throw FormulaError(at, id + "() takes " +
                                 (f->min_args == f->max_args ? std::to_string(f->min_args)
                                                             : "at least " + std::to_string(f->min_args)) +
                                 " argument(s), not " + std::to_string(args.size()));
    }
    std::string text = std::string(f->muparser) + "(";
    for (std::size_t k = 0; k < args.size(); ++k) text += (k ? "," : "") + args[k].text;
    text += ")";
    return {text, result_dimension(*f, args, where), std::nullopt, false};
  }

  Dimension result_dimension(const Function& f, const std::vector<Term>& args,
                             const std::vector<std::size_t>& where) const {
    const std::string of = std::string(f.name) + "()";
    switch (f.rule) {
      case Rule::kTrig:
        if (!(args[0].dim == units::kAngle))
          need_number(args[0], where[0], "the argument of " + of + " (an angle or a number)");
        return {};
      case Rule::kInverse: need_number(args[0], where[0], "the argument of " + of); return units::kAngle;
      case Rule::kAtan2: join(args[0], args[1], where[1], of); return units::kAngle;
      case Rule::kNumber: need_number(args[0], where[0], "the argument of " + of); return {};
      case Rule::kSqrt: {
        Dimension d;
        for (std::size_t k = 0; k < d.e.size(); ++k) {
          if (args[0].dim.e[k] % 2 != 0) {
            throw FormulaError(where[0],
                               "sqrt() of " + dimension_words(args[0].dim) + " gives a fractional power of a unit");
          }
          d.e[k] = static_cast<std::int8_t>(args[0].dim.e[k] / 2);
        }
        return d;
      }
      case Rule::kSame: return args[0].dim;
      case Rule::kSign: return {};
      case Rule::kPower: return power_dimension(args[0], args[1], where[1]);
      case Rule::kAllSame: {
        Term joined = args[0];
        for (std::size_t k = 1; k < args.size(); ++k) {
          joined.dim = join(joined, args[k], where[k], of);
          joined.zero = joined.zero && args[k].zero;
        }
        return joined.dim;
      }
    }
    return {};
  }

  const std::string& s_;
  const std::map<std::string, Dimension>& names_;
  std::size_t pos_ = 0;
  std::vector<std::string> used_;
};

}  // namespace

CheckedFormula check_formula(const std::string& text, const std::map<std::string, units::Dimension>& names) {
  return Checker(text, names).run();
}

bool is_reserved_name(const std::string& name) { return name == "pi" || find_function(name) != nullptr; }

std::string dimension_words(const units::Dimension& d) {
  if (d == units::kDimensionless) return "a plain number";
  const std::string words = units::dimension_name(d);
  const std::string si = units::example_unit(d);
  if (words.rfind("a quantity in ", 0) == 0) return words;
  return words + " (" + si + ")";
}

}  // namespace poise::kinds::formula
