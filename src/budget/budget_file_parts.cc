#include "budget/budget_file_parts.h"

#include <functional>
#include <map>

#include "budget/gain_expression.h"
#include "core/error.h"
#include "core/format.h"

namespace poise::budget {
namespace {

using engine::quote_value;
using engine::TomlReader;

std::string example(const Units& u) { return "\"4.3 " + u.unit + "\""; }

// A gain or propagation: a number or an expression muParser reads over the field variables.
std::string read_expression(TomlReader& t, const std::string& key, const std::vector<std::string>& field_names,
                            const std::string& fallback) {
  const toml::node* n = t.raw().get(key);
  if (!n) return fallback;
  t.context().used.insert(t.path(key));
  std::string text;
  if (const auto* s = n->as_string()) {
    text = s->get();
  } else if (n->is_number()) {
    text = significant(n->value<double>().value_or(0.0), 17);
  } else {
    t.error(key, engine::describe_node(*n),
            "a number or an expression of the [field] variables, e.g. \"1/cos(pitch)\"");
    return fallback;
  }
  try {
    GainExpression expr(text, field_names);
  } catch (const Error& e) {
    t.error(key, quote_value(text), e.what());
    return fallback;
  }
  return text;
}

}  // namespace

Combination parse_combination(TomlReader& t, const std::string& key, std::optional<Combination> fallback) {
  const std::optional<std::string> fb = fallback ? std::optional<std::string>(to_string(*fallback)) : std::nullopt;
  const std::string c = t.choice(key, {"rss", "linear", "bias_linear_random_rss"}, fb);
  if (c == "linear") return Combination::kLinear;
  if (c == "bias_linear_random_rss") return Combination::kBiasLinearRandomRss;
  return Combination::kRss;
}

std::optional<double> read_value(TomlReader& t, const std::string& key, const Units& u, bool allow_pixels) {
  const toml::node* n = t.raw().get(key);
  t.context().used.insert(t.path(key));
  const std::string what = units::dimension_name(u.dimension) + " with its unit, e.g. " + example(u) +
                           (allow_pixels && u.pixel ? " or \"1 px\"" : "");
  if (!n) {
    t.error(key, "", what + " (missing)");
    return std::nullopt;
  }
  const auto* s = n->as_string();
  if (!s) {
    t.error(key, engine::describe_node(*n), what + (n->is_number() ? " (missing unit)" : ""));
    return std::nullopt;
  }
  try {
    const units::Quantity q = units::parse_quantity(s->get());
    if (q.dim == u.dimension) return q.value;
    if (allow_pixels && u.pixel && q.dim == units::kPixel) return q.value * *u.pixel;
    const bool px_hint = allow_pixels && q.dim == units::kPixel;
    t.error(key, quote_value(s->get()),
            what + " (" + units::dimension_name(q.dim) + " given" +
                (px_hint ? "; [budget] pixel = \"<IFOV>\", e.g. \"18.75 arcsec\", converts pixels" : "") + ")");
  } catch (const Error& e) {
    t.error(key, quote_value(s->get()), what + " (" + e.what() + ")");
  }
  return std::nullopt;
}

Declared read_declared(TomlReader& t, const std::string& key, const Units& u) {
  Declared d;
  const toml::node* n = t.raw().get(key);
  if (!n) return d;
  d.line = t.line_of(key);
  d.as_written = engine::describe_node(*n);
  if (n->is_string()) {
    if (const auto v = read_value(t, key, u, false)) {
      d.present = true;
      d.least = d.greatest = *v;
      d.as_written = n->as_string()->get();
    }
    return d;
  }
  t.context().used.insert(t.path(key));
  const auto* arr = n->as_array();
  const std::string expected =
      "a value with its unit, e.g. " + example(u) + ", or [\"least\", \"greatest\"] over the field";
  if (!arr || arr->size() != 2 || !arr->get(0)->is_string() || !arr->get(1)->is_string()) {
    t.error(key, engine::describe_node(*n), expected);
    return d;
  }
  double ends[2] = {0, 0};
  for (std::size_t i = 0; i < 2; ++i) {
    const std::string text = arr->get(i)->as_string()->get();
    try {
      const units::Quantity q = units::parse_quantity(text);
      if (!(q.dim == u.dimension)) {
        t.error(key, quote_value(text), expected + " (" + units::dimension_name(q.dim) + " given)");
        return d;
      }
      ends[i] = q.value;
    } catch (const Error& e) {
      t.error(key, quote_value(text), expected + " (" + e.what() + ")");
      return d;
    }
  }
  if (ends[1] < ends[0]) {
    t.error(key, d.as_written, "[least, greatest]: the least first");
    return d;
  }
  d.present = d.ranged = true;
  d.least = ends[0];
  d.greatest = ends[1];
  d.as_written = "[\"" + arr->get(0)->as_string()->get() + "\", \"" + arr->get(1)->as_string()->get() + "\"]";
  return d;
}

namespace {

// A line given as a value: its contribution as given; a tolerance's keys beside it are errors.
void read_value_line(TomlReader& t, const Units& u, LineSpec& l) {
  l.given = true;
  l.value = read_value(t, "value", u, false).value_or(0.0);
  bool extra = false;
  for (const char* key : {"tolerance", "lever", "distribution", "tolerance_is", "gain", "declared"}) {
    if (t.has(key)) {
      t.error(key, "",
              std::string("no ") + key +
                  " in a line given as a value (a value line has nothing to "
                  "recompute; remove value or " +
                  key + ")");
      extra = true;
    }
  }
  if (extra) t.accept_all();  // said once above, not again as unknown keys
}

// A toleranced line's distribution and how its tolerance is stated, checked together.
void read_line_distribution(TomlReader& t, LineSpec& l) {
  const std::size_t errors_before = t.context().errors.size();
  const std::string dist = t.choice("distribution", {"normal", "uniform", "arcsine", "truncated_normal", "fixed"});
  l.distribution = sampling::parse_distribution_kind(dist);
  const bool fixed = l.distribution == sampling::DistributionKind::kFixed;
  const std::string conv = t.choice("tolerance_is", {"bounds", "1sigma", "2sigma", "3sigma"},
                                    fixed ? std::optional<std::string>("bounds") : std::nullopt);
  l.convention = sampling::parse_convention(conv);
  if (fixed && l.kind == LineKind::kRandom) {
    t.error("distribution", "\"fixed\"",
            "kind = \"bias\" for a fixed value (a fixed value does not vary: it is a bias)");
  }
  if (t.context().errors.size() == errors_before) {
    try {
      sampling::Distribution(l.distribution, 0.0, 0.0, l.convention);
    } catch (const Error& e) {
      t.error("distribution", "\"" + dist + "\" with tolerance_is \"" + conv + "\"", e.what());
    }
  }
}

}  // namespace

LineSpec read_line(TomlReader& t, const Units& u, const std::vector<std::string>& field_names) {
  LineSpec l;
  l.path = t.prefix();
  l.line = static_cast<int>(t.raw().source().begin.line);
  l.name = t.string("name");
  l.name_line = t.line_of("name");
  l.kind = t.choice("kind", {"random", "bias"}, "random") == "bias" ? LineKind::kBias : LineKind::kRandom;
  t.accept_notes();
  l.model_key = t.string("model_key", "");
  l.model_key_line = t.line_of("model_key");
  l.propagation = read_expression(t, "propagation", field_names, "");
  l.propagation_line = t.line_of("propagation");
  if (t.has("value")) {
    read_value_line(t, u, l);
    return l;
  }
  const bool angle_budget = u.dimension == units::kAngle;
  if (!t.has("tolerance")) {
    if (t.has("lever")) {
      t.error("lever", "",
              "a tolerance to go with the lever (the lever turns a length tolerance into an angle; "
              "tolerance missing)");
    } else {
      t.error("tolerance", "",
              "a tolerance (with distribution and tolerance_is), or a value: the line's "
              "contribution as given (both missing)");
    }
    t.accept_all();  // the line's other keys are not checked further
    return l;
  }
  auto text_of = [&](const char* key) {
    const auto* s = t.raw().get(key) ? t.raw().get(key)->as_string() : nullptr;
    return s ? s->get() : std::string();
  };
  l.tolerance_text = text_of("tolerance");
  if (t.has("lever")) {
    l.lever_text = text_of("lever");
    if (!angle_budget) {
      t.error("lever", quote_value(l.lever_text),
              "no lever in a budget in " + u.unit +
                  " (a lever turns a length into an angle; the budget's unit is "
                  "not an angle)");
    } else {
      l.lever = t.quantity("lever", units::kLength, engine::positive);
      l.tolerance = t.quantity("tolerance", units::kLength, engine::non_negative);
    }
  } else {
    l.tolerance = t.quantity("tolerance", u.dimension, engine::non_negative);
  }
  read_line_distribution(t, l);
  l.gain = read_expression(t, "gain", field_names, "1");
  l.gain_line = t.line_of("gain");
  l.declared = read_declared(t, "declared", u);
  return l;
}

GroupSpec read_group(TomlReader& t, const Units& u, const std::vector<std::string>& field_names, Combination fallback) {
  GroupSpec g;
  g.path = t.prefix();
  g.line = static_cast<int>(t.raw().source().begin.line);
  g.name = t.string("name");
  g.name_line = t.line_of("name");
  g.members_line = t.line_of("members");
  t.accept_notes();
  g.members = t.string_array("members");
  if (t.has("members") && g.members.empty()) t.error("members", "[]", "the names of its lines or groups (none given)");
  g.combination = parse_combination(t, "combination", fallback);
  g.propagation = read_expression(t, "propagation", field_names, "");
  g.propagation_line = t.line_of("propagation");
  g.declared = read_declared(t, "declared", u);
  return g;
}

void check_structure(const BudgetSpec& b, engine::ReadContext& ctx) {
  std::map<std::string, std::string> where;  // name -> path, first seen
  auto add = [&](const std::string& name, const std::string& path, int line) {
    if (name.empty()) return;
    const auto [it, fresh] = where.emplace(name, path);
    if (!fresh) {
      ctx.errors.emplace_back(SourceLocation{b.file, line, 0}, path + ".name", quote_value(name),
                              "a name no other line or group has (" + it->second + " has it)");
    }
  };
  for (const auto& l : b.lines) add(l.name, l.path, l.name_line ? l.name_line : l.line);
  for (const auto& g : b.groups) add(g.name, g.path, g.name_line ? g.name_line : g.line);
  std::map<std::string, std::string> parent;  // member -> group
  std::map<std::string, const GroupSpec*> groups;
  for (const auto& g : b.groups) groups[g.name] = &g;
  for (const auto& g : b.groups) {
    for (const auto& m : g.members) {
      if (!where.count(m)) {
        ctx.errors.emplace_back(SourceLocation{b.file, g.members_line, 0}, g.path + ".members", quote_value(m),
                                "the name of a [[line]] or [[group]] of this file (no such name)");
      } else if (const auto [it, fresh] = parent.emplace(m, g.name); !fresh) {
        ctx.errors.emplace_back(SourceLocation{b.file, g.members_line, 0}, g.path + ".members", quote_value(m),
                                "a member of one group only (already in group \"" + it->second + "\")");
      }
    }
  }
  // A group may not contain itself, directly or through other groups.
  for (const auto& g : b.groups) {
    std::string at = g.name;
    for (std::size_t steps = 0; parent.count(at) && steps <= b.groups.size(); ++steps) {
      at = parent.at(at);
      if (at == g.name) {
        ctx.errors.emplace_back(SourceLocation{b.file, g.members_line, 0}, g.path + ".members", quote_value(g.name),
                                "groups that do not contain themselves (a cycle through group \"" + g.name + "\")");
        break;
      }
    }
  }
}

}  // namespace poise::budget
