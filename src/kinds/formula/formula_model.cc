#include "kinds/formula/formula_model.h"

#include <algorithm>
#include <cctype>
#include <charconv>

#include "engine/kind_interface/declared_model.h"
#include "engine/study_files/model_overrides.h"
#include "engine/study_files/toml_reader.h"

namespace poise::kinds::formula {
using namespace poise::engine;
namespace {
using engine::TomlReader;

bool reserved(const std::string& name) { return is_reserved_name(name); }

// Reads the formulas of [[quantity]] (outputs = false) or [[output]] and checks them over
// `names` (each quantity's name joins them for the formulas after it).
std::vector<NamedFormula> read_formulas(TomlReader& root, bool outputs,
                                        std::map<std::string, units::Dimension>& names) {
  std::vector<NamedFormula> out;
  engine::ReadContext& ctx = root.context();
  for (TomlReader& t : root.table_array(outputs ? "output" : "quantity")) {
    NamedFormula f;
    f.name = t.string("name");
    f.text = t.string("formula");
    f.unit = t.string("unit", outputs ? std::nullopt : std::optional<std::string>(""));
    f.description = t.string("description", "");
    if (t.schema_only()) continue;
    const std::string fault = engine::declared_name_fault(f.name, names, reserved);
    if (!fault.empty()) t.error("name", engine::quote_value(f.name), fault);
    std::optional<units::Dimension> declared;
    if (!f.unit.empty()) {
      try {
        declared = engine::unit_quantity(f.unit).dim;
      } catch (const Error& e) {
        t.error("unit", engine::quote_value(f.unit), std::string("a unit, e.g. \"mm\" (") + e.what() + ")");
      }
    }
    try {
      f.checked = check_formula(f.text, names);
    } catch (const FormulaError& e) {
      const toml::node* n = t.raw().get("formula");
      const int column = n ? static_cast<int>(n->source().begin.column) + 1 + static_cast<int>(e.offset()) : 0;
      ctx.errors.emplace_back(
          SourceLocation{ctx.file, t.line_of("formula"), column}, t.path("formula"), engine::quote_value(f.text),
          "a formula with units (" + std::string(e.what()) + ", at column " + std::to_string(column) + ")");
      out.push_back(std::move(f));
      continue;
    }
    if (declared && !(*declared == f.checked.dimension)) {
      std::string why = "a formula of " + dimension_words(*declared) + ", as the unit " + f.unit + " of " + f.name +
                        " declares: this one gives " + dimension_words(f.checked.dimension);
      units::Dimension without_angle = f.checked.dimension;
      without_angle.e[4] = declared->e[4];
      if (without_angle == *declared) {
        why +=
            "; an angle is not a ratio: multiply by 1 rad (or use atan) where a ratio is a small angle, divide "
            "by 1 rad where an angle multiplies a length";
      }
      const toml::node* n = t.raw().get("formula");
      ctx.errors.emplace_back(
          SourceLocation{ctx.file, t.line_of("formula"), n ? static_cast<int>(n->source().begin.column) : 0},
          t.path("formula"), engine::quote_value(f.text), why);
    }
    if (fault.empty()) names[f.name] = f.checked.dimension;
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace

FormulaModel read_formula_model(const std::string& path, const std::map<std::string, std::string>& overrides) {
  engine::ModelDocument m = engine::open_model_file(path, overrides);
  TomlReader root(m.doc, m.ctx);
  FormulaModel f;
  f.declaration.name = "formula";
  std::map<std::string, units::Dimension> names;
  f.declaration.parameters = engine::declared_parameters(root, m.doc, names, reserved);
  f.model = engine::read_closed_form_model(f.declaration, root);
  f.quantities = read_formulas(root, false, names);
  f.outputs = read_formulas(root, true, names);
  if (f.outputs.empty() && !root.schema_only()) {
    root.error("output", "", "at least one [[output]] with name, unit and formula");
  }
  for (const NamedFormula& o : f.outputs) f.declaration.outputs.push_back({o.name, o.unit, o.description});
  engine::finish(m.doc, *m.ctx);
  return f;
}

}  // namespace poise::kinds::formula
