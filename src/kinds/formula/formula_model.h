#pragma once
/// The model file of a formula study: a mechanism of the user's own, without C++.
///
///     [model]
///     kind = "formula"
///     name = "bearing stack axial gap"
///     source = "drawing 208-1, rev C"
///
///     [parameters]                       # every value with its unit (a plain number: no unit)
///     shaft = "208 mm"
///     ring = "1.75 mm"
///
///     [tolerances.shaft]                 # as for every kind (engine/study_files/tolerance_spec.h)
///     tolerance = "0.036 mm"
///     distribution = "normal"
///     tolerance_is = "3sigma"
///     [tolerances.ring]
///     deviation = ["0 mm", "+0.06 mm"]   # a drawing's asymmetric limits
///     distribution = "normal"
///     tolerance_is = "3sigma"
///
///     [[quantity]]                       # optional: a named intermediate, usable by later formulas
///     name = "rings"
///     formula = "2 * ring"
///     unit = "mm"                        # optional: checked when given
///
///     [[output]]                         # one or more: a column of samples.csv
///     name = "gap"
///     unit = "mm"                        # the formula's value must have this unit's dimension
///     formula = "shaft - rings - 2 * 23 mm"
///     description = "axial play of the stack"
///
/// Every formula is checked when the file is read (kinds/formula/unit_formula.h): an unknown
/// name with the nearest one, a syntax error, a dimension that does not agree, each with file,
/// line and column. Parameters are inputs in the order the file gives them; a name must be a
/// word of letters, digits and _ not taken by a function of the formulas.
#include <map>
#include <string>
#include <vector>

#include "engine/kind_interface/closed_form_study.h"
#include "kinds/formula/unit_formula.h"

namespace poise::kinds::formula {

/// A named formula of the model: a quantity or an output.
struct NamedFormula {
  std::string name;
  std::string unit;  ///< declared (outputs always; quantities when given)
  std::string description;
  std::string text;  ///< as written
  CheckedFormula checked;
};

/// A formula model as read and checked.
struct FormulaModel {
  engine::ClosedFormDeclaration declaration;  ///< parameters (from the file) and outputs
  engine::ClosedFormModel model;              ///< values and tolerances
  std::vector<NamedFormula> quantities, outputs;
};

/// Reads and checks the model file at `path` with `overrides` on it. Throws ValidationError
/// naming file, line, column, key and what was expected, for every fault at once.
FormulaModel read_formula_model(const std::string& path, const std::map<std::string, std::string>& overrides);

}  // namespace poise::kinds::formula
