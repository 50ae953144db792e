#pragma once
/// A formula with units, checked when it is read and evaluated by muParser (libmuparser-dev).
///
/// The language is muParser's arithmetic with units on its constants:
///   numbers         2, 0.5, 1e-3, and constants with a unit: "23 mm", "9.81 m/s^2", "1 rad"
///                   (a number followed by a unit word is a constant, never a product: "2 s" is
///                   two seconds even beside a parameter s; a compound unit is written without
///                   spaces, "N*m", "m/s^2", and a spaced operator ends it: "2 mm * x")
///   names           the model's parameters and the quantities declared before; `pi`
///   operators       + - * / ^ (power: right-associative, -x^2 = -(x^2)), comparisons
///                   < <= > >= == !=, && ||, and cond ? a : b
///   functions       sin cos tan (of an angle or a number), asin acos atan (give an angle),
///                   atan2(y, x) (an angle), sinh cosh tanh asinh acosh atanh exp ln log
///                   (natural) log10 log2 (of numbers), sqrt, abs, sign, rint, floor, ceil,
///                   min max sum avg hypot (of arguments of one dimension), pow(x, y) (as x^y,
///                   but by the C library's pow, where x^y is muParser's own)
///
/// Dimensions are checked on the whole tree (core/units.h: length, mass, time, current, angle,
/// pixel, temperature): + - comparisons, min/max and the two branches of ?: need one
/// dimension (a bare 0 takes any); x^y needs y a number, and a constant one unless x is
/// dimensionless (the exponents of x^y must come out whole); sqrt halves them. Angles are a
/// dimension of their own, as everywhere in Poise: a ratio is not an angle until it is
/// multiplied by "1 rad" (or passed through atan).
///
/// Not our own evaluator: the checked tree is written back as fully parenthesised muParser
/// text (constants in SI), which muParser compiles to its bytecode once per thread.
#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/units.h"

namespace poise::kinds::formula {

/// A formula refused: what is wrong and where (0-based offset into the formula's text).
class FormulaError : public Error {
 public:
  FormulaError(std::size_t offset, const std::string& message) : Error(message), offset_(offset) {}
  std::size_t offset() const { return offset_; }

 private:
  std::size_t offset_;
};

/// A formula after its check.
struct CheckedFormula {
  units::Dimension dimension;      ///< of its value
  std::string muparser_text;       ///< fully parenthesised, constants in SI
  std::vector<std::string> names;  ///< the declared names it uses, in order of first use
};

/// Parses `text` over names of known dimension. Throws FormulaError (unknown name, with the
/// nearest one; syntax; dimensions that do not agree), with the offset of the fault.
CheckedFormula check_formula(const std::string& text, const std::map<std::string, units::Dimension>& names);

/// Whether `name` is a function or constant of the language (a parameter may not take it).
bool is_reserved_name(const std::string& name);

/// A dimension in words with its SI units: "a length (m)", "a quantity in m^2".
std::string dimension_words(const units::Dimension& d);

}  // namespace poise::kinds::formula
