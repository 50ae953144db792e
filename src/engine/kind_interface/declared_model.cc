#include "engine/kind_interface/declared_model.h"

#include <algorithm>
#include <cctype>
#include <charconv>

#include "engine/study_files/model_overrides.h"

namespace poise::engine {
namespace {

bool is_word(const std::string& s) {
  if (s.empty() || !std::isalpha(static_cast<unsigned char>(s[0]))) return false;
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

// The unit written after a value's number ("208 mm" -> "mm"; "0.3" -> "").
std::string written_unit(const std::string& text) {
  const std::size_t p = text.find_first_not_of(" \t");
  if (p == std::string::npos) return "";
  double x = 0.0;
  const auto res = std::from_chars(text.data() + p, text.data() + text.size(), x);
  if (res.ec != std::errc()) return "";
  const std::string rest = text.substr(static_cast<std::size_t>(res.ptr - text.data()));
  const std::size_t b = rest.find_first_not_of(" \t"), e = rest.find_last_not_of(" \t");
  return b == std::string::npos ? "" : rest.substr(b, e - b + 1);
}

}  // namespace

std::string declared_name_fault(const std::string& name, const std::map<std::string, units::Dimension>& taken,
                                const std::function<bool(const std::string&)>& reserved) {
  if (!is_word(name)) return "a name of letters, digits and _ that starts with a letter";
  if (reserved && reserved(name))
    return "a name that is not a function or constant of the formulas (" + name + " is one)";
  if (taken.count(name)) return "a name not declared before (" + name + " is)";
  return "";
}

std::vector<ClosedFormParameter> declared_parameters(TomlReader& root, const toml::table& doc,
                                                     std::map<std::string, units::Dimension>& taken,
                                                     const std::function<bool(const std::string&)>& reserved) {
  std::vector<ClosedFormParameter> out;
  if (root.schema_only()) {  // `poise keys`: a stand-in parameter shows the keys
    root.table("parameters")
        .ask("NAME", "a value with its unit, e.g. \"208 mm\", or a plain number (one key each)", "", true);
    return {{"NAME", units::kLength, "mm", "a parameter"}};
  }
  ReadContext& ctx = root.context();
  const toml::table* table = doc["parameters"].as_table();
  if (!table) return out;  // read_closed_form_model says it is missing
  std::vector<std::pair<toml::source_position, std::string>> keys;
  for (const auto& [key, node] : *table) keys.emplace_back(node.source().begin, std::string(key.str()));
  std::sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) {
    return a.first.line != b.first.line ? a.first.line < b.first.line : a.first.column < b.first.column;
  });
  for (const auto& [at, key] : keys) {
    const SourceLocation where{ctx.file, static_cast<int>(at.line), static_cast<int>(at.column)};
    const std::string fault = declared_name_fault(key, taken, reserved);
    if (!fault.empty()) {
      ctx.errors.emplace_back(where, "parameters." + key, "", fault);
      continue;
    }
    const toml::node& node = *table->get(key);
    ClosedFormParameter p{key, units::kDimensionless, "", ""};
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
    taken[key] = p.dimension;
    out.push_back(p);
  }
  return out;
}

std::vector<OutputSpec> declared_outputs(TomlReader& root, std::map<std::string, units::Dimension>& taken,
                                         const std::function<bool(const std::string&)>& reserved) {
  std::vector<OutputSpec> out;
  auto tables = root.table_array("output");
  for (TomlReader& t : tables) {
    OutputSpec o{t.string("name"), t.string("unit"), t.string("description", "")};
    if (t.schema_only()) continue;
    const std::string fault = declared_name_fault(o.name, taken, reserved);
    if (!fault.empty()) t.error("name", quote_value(o.name), fault);
    units::Dimension dim;
    try {
      dim = unit_quantity(o.unit).dim;
    } catch (const Error& e) {
      t.error("unit", quote_value(o.unit), std::string("a unit, e.g. \"mm\" (") + e.what() + ")");
    }
    taken[o.name] = dim;
    out.push_back(o);
  }
  if (tables.empty() && !root.schema_only()) root.error("output", "", "at least one [[output]] with name and unit");
  return out;
}

DeclaredModel read_declared_model(const std::string& path, const std::map<std::string, std::string>& overrides,
                                  const std::string& kind, const std::function<void(TomlReader& model)>& model_keys) {
  ModelDocument m = open_model_file(path, overrides);
  TomlReader root(m.doc, m.ctx);
  DeclaredModel d;
  d.declaration.name = kind;
  std::map<std::string, units::Dimension> names;
  d.declaration.parameters = declared_parameters(root, m.doc, names, {});
  d.model = read_closed_form_model(d.declaration, root);
  TomlReader model = root.table("model");
  model_keys(model);
  d.declaration.outputs = declared_outputs(root, names, {});
  finish(m.doc, *m.ctx);
  return d;
}

DeclaredUnitsFunction::DeclaredUnitsFunction(const ClosedFormDeclaration& declaration) {
  for (const auto& p : declaration.parameters) {
    inputs_.push_back(p.name);
    in_factor_.push_back(unit_quantity(p.display_unit).value);
  }
  for (const auto& o : declaration.outputs) {
    outputs_.push_back(o.name);
    out_factor_.push_back(unit_quantity(o.unit).value);
  }
}

void DeclaredUnitsFunction::compute(std::span<const double> parameters, std::span<double> outputs) {
  std::vector<std::string> failures;
  const std::size_t id = 0;
  compute_batch(std::span<const std::size_t>(&id, 1), parameters, outputs, failures);
  if (!failures[0].empty()) throw Error(failures[0]);
}

void DeclaredUnitsFunction::compute_batch(std::span<const std::size_t> ids, std::span<const double> parameters,
                                          std::span<double> outputs, std::vector<std::string>& failures) {
  const std::size_t n = ids.size(), p = in_factor_.size(), q = out_factor_.size();
  std::vector<double> in(parameters.begin(), parameters.end());
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t k = 0; k < p; ++k) in[r * p + k] /= in_factor_[k];
  }
  failures.assign(n, "");
  evaluate(ids, in, outputs, failures);
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t k = 0; k < q; ++k) outputs[r * q + k] *= out_factor_[k];
  }
}

}  // namespace poise::engine
