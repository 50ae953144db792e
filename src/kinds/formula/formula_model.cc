#include "kinds/formula/formula_model.h"

#include <algorithm>
#include <cctype>
#include <charconv>

#include "engine/study_files/model_overrides.h"
#include "engine/study_files/toml_reader.h"

namespace poise::kinds::formula {
namespace {
using engine::TomlReader;

bool is_identifier(const std::string& s) {
  if (s.empty() || !std::isalpha(static_cast<unsigned char>(s[0]))) return false;
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

// What is wrong with a name for a parameter, quantity or output ("" if nothing).
std::string name_fault(const std::string& name, const std::map<std::string, units::Dimension>& taken) {
  if (!is_identifier(name)) return "a name of letters, digits and _ that starts with a letter";
  if (is_reserved_name(name)) return "a name that is not a function or constant of the formulas (" + name + " is one)";
  if (taken.count(name)) return "a name not declared before (" + name + " is)";
  return "";
}

// The unit written after a value's number ("208 mm" -> "mm"; "0.3" -> "").
std::string written_unit(const std::string& text) {
  std::size_t p = text.find_first_not_of(" \t");
  if (p == std::string::npos) return "";
  double x = 0.0;
  const auto res = std::from_chars(text.data() + p, text.data() + text.size(), x);
  if (res.ec != std::errc()) return "";
  const std::string rest = text.substr(static_cast<std::size_t>(res.ptr - text.data()));
  const std::size_t b = rest.find_first_not_of(" \t"), e = rest.find_last_not_of(" \t");
  return b == std::string::npos ? "" : rest.substr(b, e - b + 1);
}

// The parameters in the order the file gives them, with their dimension and written unit.
std::vector<engine::ClosedFormParameter> file_parameters(const toml::table& doc, engine::ReadContext& ctx,
                                                         std::map<std::string, units::Dimension>& names) {
  std::vector<engine::ClosedFormParameter> out;
  const toml::table* table = doc["parameters"].as_table();
  if (!table) return out;  // read_closed_form_model says it is missing
  std::vector<std::pair<toml::source_position, std::string>> keys;
  for (const auto& [key, node] : *table) keys.emplace_back(node.source().begin, std::string(key.str()));
  std::sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) {
    return a.first.line != b.first.line ? a.first.line < b.first.line : a.first.column < b.first.column;
  });
  for (const auto& [at, key] : keys) {
    const SourceLocation where{ctx.file, static_cast<int>(at.line), static_cast<int>(at.column)};
    const std::string fault = name_fault(key, names);
    if (!fault.empty()) {
      ctx.errors.emplace_back(where, "parameters." + key, "", fault);
      continue;
    }
    const toml::node& node = *table->get(key);
    engine::ClosedFormParameter p{key, units::kDimensionless, "", ""};
    if (const auto* s = node.as_string()) {
      try {
        p.dimension = units::parse_quantity(s->get()).dim;
        p.display_unit = written_unit(s->get());
      } catch (const Error&) {
        // read_closed_form_model reports the value with what is expected.
      }
    } else if (!node.is_number()) {
      ctx.errors.emplace_back(where, "parameters." + key, "", "a value with its unit, e.g. \"208 mm\", or a number");
      continue;
    }
    names[key] = p.dimension;
    out.push_back(p);
  }
  return out;
}

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
    const std::string fault = name_fault(f.name, names);
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
  if (root.schema_only()) {  // `poise keys formula`: a stand-in parameter shows the keys
    f.declaration.parameters.push_back({"NAME", units::kLength, "mm", "a parameter"});
    root.table("parameters")
        .ask("NAME", "a value with its unit, e.g. \"208 mm\", or a plain number (one key each)", "", true);
  } else {
    f.declaration.parameters = file_parameters(m.doc, *m.ctx, names);
  }
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
