#include "budget/budget_file.h"

#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "budget/budget_evaluation.h"
#include "budget/budget_file_parts.h"
#include "budget/field_grid.h"
#include "core/error.h"
#include "engine/study_files/toml_reader.h"

namespace poise::budget {
namespace {

using engine::quote_value;
using engine::TomlReader;

// Names muParser keeps for its own functions and constants: not usable as a variable.
const std::set<std::string>& reserved_names() {
  static const std::set<std::string> names = {
      "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "asinh", "acosh", "atanh", "log2", "log10",
      "log", "ln",  "exp", "sqrt", "sign", "rint", "abs",  "min",  "max",  "sum",   "avg",   "pi",    "_pi",  "_e"};
  return names;
}

bool is_identifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  }
  return true;
}

// A [field] range: ["-30 deg", "30 deg"] or [0.4, 0.96].
void read_range(TomlReader& t, const std::string& key, FieldVariable& v) {
  const toml::node* n = t.raw().get(key);
  t.context().used.insert(t.path(key));
  const std::string expected =
      "a range of two values with their unit, e.g. [\"-30 deg\", \"30 deg\"], or two plain numbers [0.4, 0.96]";
  const auto* arr = n ? n->as_array() : nullptr;
  if (!arr || arr->size() != 2) {
    t.error(key, n ? engine::describe_node(*n) : "", expected + (n ? "" : " (missing)"));
    return;
  }
  double ends[2] = {0, 0};
  units::Dimension dims[2]{};
  for (std::size_t i = 0; i < 2; ++i) {
    const toml::node& e = *arr->get(i);
    if (const auto* s = e.as_string()) {
      try {
        const units::Quantity q = units::parse_quantity(s->get());
        ends[i] = q.value;
        dims[i] = q.dim;
        if (i == 0) {
          const auto space = s->get().find_first_of(" \t");
          v.unit = space == std::string::npos ? "" : s->get().substr(space + 1);
          while (!v.unit.empty() && v.unit.front() == ' ') v.unit.erase(0, 1);
        }
      } catch (const Error& err) {
        t.error(key, quote_value(s->get()), expected + " (" + err.what() + ")");
        return;
      }
    } else if (e.is_number()) {
      ends[i] = e.value<double>().value_or(0.0);
    } else {
      t.error(key, engine::describe_node(e), expected);
      return;
    }
  }
  if (!(dims[0] == dims[1])) {
    t.error(key, engine::describe_node(*n),
            "both ends in the same kind of unit (" + units::dimension_name(dims[0]) + " and " +
                units::dimension_name(dims[1]) + " given)");
    return;
  }
  if (ends[1] < ends[0]) {
    t.error(key, engine::describe_node(*n), "[least, greatest]: the first end not above the second");
    return;
  }
  v.lo = ends[0];
  v.hi = ends[1];
  v.angle = dims[0] == units::kAngle;
}

void read_field(TomlReader& root, BudgetSpec& b) {
  if (!root.has("field")) return;
  TomlReader f = root.table("field");
  for (const auto& name : f.keys()) {
    FieldVariable v;
    v.name = name;
    v.line = f.line_of(name);
    if (!is_identifier(name) || reserved_names().count(name)) {
      f.error(name, "",
              "a variable name of letters, digits and '_' that is not a function or constant of "
              "expressions (sin, cos, tan, sqrt, abs, pi, ...)");
    }
    if (f.raw().get(name)->is_table()) {
      TomlReader sub = f.table(name);
      read_range(sub, "range", v);
      v.model_key = sub.string("model_key", "");
      sub.accept_notes();
    } else {
      read_range(f, name, v);
    }
    b.field.push_back(v);
  }
}

void read_model_part(TomlReader& t, BudgetSpec& b) {
  if (!t.has("model")) {
    for (const char* key : {"output", "samples", "seed"}) {
      if (t.has(key)) {
        t.error(key, "", "a model to sample: [budget] model = \"../models/x.toml\" (missing)");
        t.context().used.insert(t.path(key));  // said once, not again as an unknown key
      }
    }
    return;
  }
  b.model_as_written = t.string("model");
  b.model_line = t.line_of("model");
  b.model_path = (std::filesystem::path(b.file).parent_path() / b.model_as_written).lexically_normal().string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(b.model_path, ec)) {
    t.error("model", quote_value(b.model_as_written), "an existing model file (looked for " + b.model_path + ")");
  }
  b.output = t.string("output");
  b.output_line = t.line_of("output");
  b.samples = static_cast<std::size_t>(t.integer("samples", 10, 10'000'000, 4000));
  b.seed = static_cast<std::uint64_t>(t.integer("seed", 0, std::numeric_limits<std::int64_t>::max(), 1));
}

// [budget]: its name, unit, level, combination, field points, pixel and confidence. Whether
// the unit was understood (nothing else reads without it).
bool read_budget_table(TomlReader& t, BudgetSpec& b) {
  b.name = t.string("name");
  b.title = t.string("title", "");
  t.accept_notes();
  b.notes = t.string("notes", "");
  b.source = t.string("source", "");
  b.unit = t.string("unit");
  bool unit_ok = false;
  if (t.has("unit")) {
    try {
      b.unit_factor = units::unit_factor(b.unit);
      b.dimension = units::parse_quantity("1 " + b.unit).dim;
      unit_ok = true;
    } catch (const Error& e) {
      t.error("unit", quote_value(b.unit),
              std::string("a unit such as \"arcsec\", \"urad\" or \"mm\" (") + e.what() + ")");
    }
  }
  b.level = level_sigmas(t.choice("level", {"1sigma", "2sigma", "3sigma"}));
  b.combination = parse_combination(t, "combination", std::nullopt);
  b.field_points = static_cast<std::size_t>(t.integer("field_points", 2, 1001, 13));
  if (t.has("pixel")) b.pixel = t.quantity("pixel", units::kAngle, engine::positive);
  const double level_probability = 2.0 * sampling::standard_normal_cdf(b.level) - 1.0;
  b.confidence = t.number(
      "confidence",
      [](double p) { return p > 0.0 && p < 1.0 ? "" : "a probability between 0 and 1, e.g. 0.9973 (3 sigma)"; },
      level_probability);
  return unit_ok;
}

// [budget] requirement, declared and declared_in_pixels, in the budget's unit.
void read_requirement_and_declared(TomlReader& t, BudgetSpec& b) {
  const Units u{b.dimension, b.unit, b.pixel};
  if (t.has("requirement")) {
    b.requirement_text = t.string("requirement");
    b.requirement = read_value(t, "requirement", u, true);
    if (b.requirement && !(*b.requirement > 0)) {
      t.error("requirement", quote_value(b.requirement_text), "a positive value");
      b.requirement.reset();
    }
  }
  b.declared = read_declared(t, "declared", u);
  if (t.has("declared_in_pixels")) {
    if (!b.pixel) {
      t.error("declared_in_pixels", "", "[budget] pixel = \"<IFOV>\" to convert pixels (missing pixel)");
    } else {
      b.declared_in_pixels = read_declared(t, "declared_in_pixels", Units{units::kPixel, "px", std::nullopt});
    }
  }
}

// The [[line]]s and [[group]]s, then the structure they form.
void read_lines_and_groups(TomlReader& root, BudgetSpec& b, engine::ReadContext& ctx) {
  std::vector<std::string> field_names;
  for (const auto& v : b.field) field_names.push_back(v.name);
  const Units u{b.dimension, b.unit, b.pixel};
  for (auto& l : root.table_array("line")) b.lines.push_back(read_line(l, u, field_names));
  for (auto& g : root.table_array("group")) b.groups.push_back(read_group(g, u, field_names, b.combination));
  if (b.lines.empty()) root.error("line", "", "at least one [[line]] (none given)");
  check_structure(b, ctx);
}

// The field grid's size, then the expressions' values over it.
void check_field_grid(TomlReader& t, const BudgetSpec& b, engine::ReadContext& ctx) {
  // Each variable has its points, plus zero where it is inside the range.
  const double grid_size = std::pow(static_cast<double>(b.field_points + 1), static_cast<double>(b.field.size()));
  if (grid_size > static_cast<double>(kMaxFieldGridPoints)) {
    t.error("field_points", std::to_string(b.field_points),
            "at most " + std::to_string(kMaxFieldGridPoints) + " grid points over the " +
                std::to_string(b.field.size()) + " [field] variables (fewer points per variable)");
  } else if (ctx.errors.empty()) {
    // Expressions parsed; now their values over the field (1/cos(pitch) at 90 deg, ...).
    for (auto& e : check_expressions(b)) ctx.errors.push_back(std::move(e));
  }
}

}  // namespace

std::string to_string(Combination c) {
  switch (c) {
    case Combination::kRss: return "rss";
    case Combination::kLinear: return "linear";
    case Combination::kBiasLinearRandomRss: return "bias_linear_random_rss";
  }
  return "?";
}

int level_sigmas(const std::string& level) {
  if (level == "2sigma") return 2;
  if (level == "3sigma") return 3;
  return 1;
}

BudgetSpec load_budget(const std::string& path) {
  const toml::table doc = engine::parse_toml_file(path);
  auto ctx = std::make_shared<engine::ReadContext>();
  ctx->file = path;
  TomlReader root(doc, ctx);
  BudgetSpec b;
  b.file = path;
  if (!root.has("budget")) {  // not a budget file (a study or model file, say): say that alone
    root.table("budget");
    throw engine::ValidationError(ctx->errors);
  }
  TomlReader t = root.table("budget");
  if (!read_budget_table(t, b)) throw engine::ValidationError(ctx->errors);  // nothing else reads without it
  read_requirement_and_declared(t, b);
  read_model_part(t, b);
  read_field(root, b);
  read_lines_and_groups(root, b, *ctx);
  check_field_grid(t, b, *ctx);
  engine::finish(doc, *ctx);
  return b;
}

}  // namespace poise::budget
