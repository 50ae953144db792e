// TomlReader: a view of one table of a study or model file, its navigation (tables, arrays
// of tables, keys) and its typed getters (string, choice, quantity, number, integer,
// boolean, string array), each recording the key it asks for; the checks positive and
// non_negative.
#include "engine/study_files/toml_reader.h"

#include "core/nearest_name.h"

#include "engine/study_files/toml_reader_detail.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

namespace poise::engine {
namespace {
using detail::location_of;
using detail::schema_path;

std::string describe_number(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}
}  // namespace

TomlReader::TomlReader(const toml::table& table, std::shared_ptr<ReadContext> ctx, std::string prefix)
    : table_(&table), ctx_(std::move(ctx)), prefix_(std::move(prefix)) {}

std::string TomlReader::path(const std::string& key) const { return prefix_.empty() ? key : prefix_ + "." + key; }

bool TomlReader::has(const std::string& key) const { return table_->contains(key); }

int TomlReader::line_of(const std::string& key) const {
  const toml::node* n = table_->get(key);
  return n ? static_cast<int>(n->source().begin.line) : 0;
}

void TomlReader::ask(const std::string& key, const std::string& expected, const std::string& fallback, bool required) {
  const std::string p = schema_path(path(key));
  for (const auto& k : ctx_->asked) {
    if (k.path == p) return;
  }
  ctx_->asked.push_back({p, expected, fallback, required});
}

const toml::node* TomlReader::node(const std::string& key) {
  const toml::node* n = table_->get(key);
  if (n) ctx_->used.insert(path(key));
  return n;
}

void TomlReader::error(const std::string& key, const std::string& value, const std::string& expected) {
  if (schema_only()) return;
  const toml::node* n = table_->get(key);
  SourceLocation loc = location_of(ctx_->file, n);
  if (!n) {  // missing key: point at the table
    loc.line = static_cast<int>(table_->source().begin.line);
    loc.column = 0;
  }
  ctx_->errors.emplace_back(loc, path(key), value, expected);
}

TomlReader TomlReader::table(const std::string& key, bool required) {
  static const toml::table kEmpty;
  ask(key, "a table [" + schema_path(path(key)) + "]", required ? "" : "(optional)", required);
  const toml::node* n = node(key);
  if (!n) {
    if (required) error(key, "", "a table [" + path(key) + "] (missing)");
    return TomlReader(kEmpty, ctx_, path(key));
  }
  if (!n->is_table()) {
    error(key, describe_node(*n), "a table [" + path(key) + "]");
    return TomlReader(kEmpty, ctx_, path(key));
  }
  return TomlReader(*n->as_table(), ctx_, path(key));
}

std::vector<std::string> TomlReader::keys() const {
  std::vector<std::pair<int, std::string>> ordered;
  for (const auto& [k, v] : *table_) {
    ordered.emplace_back(static_cast<int>(v.source().begin.line), std::string(k.str()));
  }
  std::stable_sort(ordered.begin(), ordered.end());
  std::vector<std::string> out;
  out.reserve(ordered.size());
  for (auto& p : ordered) out.push_back(p.second);
  return out;
}

std::vector<TomlReader> TomlReader::table_array(const std::string& key) {
  static const toml::table kEmpty;
  std::vector<TomlReader> out;
  ask(key, "tables [[" + schema_path(path(key)) + "]]", "(optional)", false);
  const toml::node* n = node(key);
  if (!n && schema_only()) out.emplace_back(kEmpty, ctx_, path(key) + "[]");  // its keys, for the schema
  if (!n) return out;
  const auto* arr = n->as_array();
  if (!arr || (!arr->empty() && !arr->is_array_of_tables())) {  // an empty array: none
    error(key, describe_node(*n), "an array of tables [[" + path(key) + "]]");
    return out;
  }
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const std::string p = path(key) + "[" + std::to_string(i) + "]";
    out.emplace_back(*arr->get(i)->as_table(), ctx_, p);
  }
  return out;
}

std::string TomlReader::string(const std::string& key, std::optional<std::string> fallback) {
  ask(key, "a string", fallback ? (fallback->empty() ? "\"\"" : "\"" + *fallback + "\"") : "", !fallback);
  const toml::node* n = node(key);
  if (!n) {
    if (!fallback) error(key, "", "a string (missing)");
    return fallback.value_or("");
  }
  if (const auto* s = n->as_string()) return s->get();
  error(key, describe_node(*n), "a string in quotes");
  return fallback.value_or("");
}

std::string TomlReader::choice(const std::string& key, const std::vector<std::string>& choices,
                               std::optional<std::string> fallback) {
  std::string options;
  for (const auto& c : choices) options += (options.empty() ? "\"" : " | \"") + c + "\"";
  ask(key, "one of " + options, fallback ? "\"" + *fallback + "\"" : "", !fallback);
  if (schema_only()) {
    const toml::node* n = node(key);
    if (n && n->is_string()) return n->as_string()->get();
    return fallback ? *fallback : choices.front();
  }
  const bool present = has(key);
  std::string v = string(key, fallback ? fallback : std::optional<std::string>(""));
  if (!present && !fallback) {
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "\"" : ", \"") + c + "\"";
    error(key, "", "one of " + list + " (missing)");
    return choices.front();
  }
  for (const auto& c : choices) {
    if (c == v) return v;
  }
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "\"" : ", \"") + c + "\"";
  error(key, quote_value(v), "one of " + list + did_you_mean(v, choices));
  return choices.front();
}

double TomlReader::quantity(const std::string& key, const units::Dimension& dim,
                            const std::function<std::string(double)>& check, std::optional<double> fallback) {
  const std::string example = units::example_unit(dim);
  ask(key, units::dimension_name(dim) + " with its unit, e.g. \"1 " + example + "\"",
      fallback ? units::format(*fallback, example) : "", !fallback);
  if (schema_only()) {  // a value the check accepts, so that readers go on
    node(key);
    if (fallback) return *fallback;
    for (double v : {1.0, 0.5, 0.0, -1.0}) {
      if (!check || check(v).empty()) return v;
    }
    return 1.0;
  }
  const toml::node* n = node(key);
  if (!n) {
    if (!fallback) {
      error(key, "", units::dimension_name(dim) + " with its unit, e.g. \"1 " + example + "\" (missing)");
    }
    return fallback.value_or(0.0);
  }
  const auto* s = n->as_string();
  if (!s) {
    if (n->is_number() && !(dim == units::kDimensionless)) {
      error(key, describe_node(*n),
            units::dimension_name(dim) + " with its unit in quotes, e.g. \"" + describe_node(*n) + " " + example +
                "\" (missing unit)");
    } else {
      error(key, describe_node(*n), units::dimension_name(dim) + " as a string, e.g. \"1 " + example + "\"");
    }
    return fallback.value_or(0.0);
  }
  try {
    const double v = units::parse_as(s->get(), dim);
    if (check) {
      const std::string problem = check(v);
      if (!problem.empty()) {
        error(key, describe_node(*n), problem);
        return fallback.value_or(v);
      }
    }
    return v;
  } catch (const Error& e) {
    // units::parse_as says "<problem>; expected <what>" (or "wrong unit: got <x>, expected
    // <what>"): lead with what was expected.
    const std::string msg = e.what();
    auto split = msg.find("; expected ");
    if (split == std::string::npos) split = msg.find(", expected ");
    error(key, describe_node(*n),
          split == std::string::npos ? msg : msg.substr(split + 11) + " (" + msg.substr(0, split) + ")");
    return fallback.value_or(0.0);
  }
}

double TomlReader::number(const std::string& key, const std::function<std::string(double)>& check,
                          std::optional<double> fallback) {
  ask(key, "a plain number (no unit)", fallback ? describe_number(*fallback) : "", !fallback);
  if (schema_only()) {
    node(key);
    if (fallback) return *fallback;
    for (double v : {1.0, 0.5, 0.0, -1.0}) {
      if (!check || check(v).empty()) return v;
    }
    return 1.0;
  }
  const toml::node* n = node(key);
  if (!n) {
    if (!fallback) error(key, "", "a number (missing)");
    return fallback.value_or(0.0);
  }
  std::optional<double> v;
  if (const auto* f = n->as_floating_point()) v = f->get();
  if (const auto* i = n->as_integer()) v = static_cast<double>(i->get());
  if (!v) {
    error(key, describe_node(*n), "a plain number (no unit), e.g. 0.4");
    return fallback.value_or(0.0);
  }
  if (!std::isfinite(*v)) {  // TOML has nan and inf; no input of Poise means them
    error(key, describe_node(*n), "a finite number");
    return fallback.value_or(0.0);
  }
  if (check) {
    const std::string problem = check(*v);
    if (!problem.empty()) {
      error(key, describe_node(*n), problem);
      return fallback.value_or(*v);
    }
  }
  return *v;
}

std::int64_t TomlReader::integer(const std::string& key, std::int64_t min, std::int64_t max,
                                 std::optional<std::int64_t> fallback) {
  const std::string range = "an integer from " + std::to_string(min) + " to " + std::to_string(max);
  ask(key, range, fallback ? std::to_string(*fallback) : "", !fallback);
  const toml::node* n = node(key);
  if (!n) {
    if (!fallback) error(key, "", range + " (missing)");
    return fallback.value_or(min);
  }
  const auto* i = n->as_integer();
  if (!i || i->get() < min || i->get() > max) {
    error(key, describe_node(*n), range);
    return fallback.value_or(min);
  }
  return i->get();
}

bool TomlReader::boolean(const std::string& key, std::optional<bool> fallback) {
  ask(key, "true or false", fallback ? (*fallback ? "true" : "false") : "", !fallback);
  const toml::node* n = node(key);
  if (!n) {
    if (!fallback) error(key, "", "true or false (missing)");
    return fallback.value_or(false);
  }
  if (const auto* b = n->as_boolean()) return b->get();
  error(key, describe_node(*n), "true or false");
  return fallback.value_or(false);
}

std::vector<std::string> TomlReader::string_array(const std::string& key) {
  std::vector<std::string> out;
  ask(key, "an array of strings", "", true);
  const toml::node* n = node(key);
  if (!n) {
    error(key, "", "an array of strings (missing)");
    return out;
  }
  const auto* arr = n->as_array();
  if (!arr) {
    error(key, describe_node(*n), "an array of strings, e.g. [\"60 mm\", \"82 mm\"]");
    return out;
  }
  for (const auto& el : *arr) {
    if (const auto* s = el.as_string()) {
      out.push_back(s->get());
    } else {
      error(key, describe_node(el), "an array of strings only");
    }
  }
  return out;
}

void TomlReader::accept_all() {
  for (const auto& [k, v] : *table_) {
    ctx_->used.insert(path(std::string(k.str())));
    if (v.is_table()) TomlReader(*v.as_table(), ctx_, path(std::string(k.str()))).accept_all();
  }
}

void TomlReader::accept_notes() {
  string("notes", "");
  string("source", "");
}

std::string positive(double v) { return v > 0 ? "" : "a positive value"; }
std::string non_negative(double v) { return v >= 0 ? "" : "a value >= 0"; }

}  // namespace poise::engine
