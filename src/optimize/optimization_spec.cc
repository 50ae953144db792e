#include "optimize/optimization_spec.h"

#include "engine/kind_interface/study_kind.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/error.h"
#include "core/format.h"
#include "core/units.h"
#include "engine/kind_interface/study_evaluation.h"
#include "engine/study_files/toml_reader.h"
#include "sampling/design.h"

namespace poise::optimize {
namespace {
namespace fs = std::filesystem;
using engine::TomlReader;

// "3 mm" -> (3, "mm"); "0.5" -> (0.5, "").
std::pair<double, std::string> number_and_unit(TomlReader& t, const std::string& key, bool* ok) {
  const std::string text = t.string(key);
  std::istringstream in(text);
  double v = NAN;
  in >> v;
  std::string unit;
  std::getline(in >> std::ws, unit);
  *ok = static_cast<bool>(in) || in.eof();
  if (!std::isfinite(v)) {
    t.error(key, "\"" + text + "\"", "a number with its unit, e.g. \"4 mm\"");
    *ok = false;
  } else if (!unit.empty()) {
    try {
      units::unit_factor(unit);
    } catch (const Error& e) {
      t.error(key, "\"" + text + "\"", std::string("a known unit (") + e.what() + ")");
      *ok = false;
    }
  }
  return {v, unit};
}

// SplitMix64 of (base, k): seeds for the search replicates and the fresh sets.
std::uint64_t mix(std::uint64_t base, std::uint64_t k) {
  std::uint64_t z = base + 0x9E3779B97F4A7C15ULL * (k + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return (z ^ (z >> 31)) & 0x7FFFFFFFFFFFFFFFULL;
}

constexpr const char* kStatistics = "mean, std, min, max, p<q> (p95, p99.73), fraction_le:<x>, fraction_ge:<x>";

}  // namespace

std::string value_text(double value, const std::string& unit) {
  const std::string text = significant(value, 10);
  return unit.empty() ? text : text + " " + unit;
}

std::string Requirement::describe() const {
  return statistic + " of " + output + (bound.side == BoundSide::kNone ? "" : " (" + optimize::describe(bound) + ")") +
         (at_least ? " >= " : " <= ") + value_text(limit(), "");
}

std::uint64_t OptimizationSpec::replicate_seed(int r) const {
  return r == 0 ? seed : mix(seed, static_cast<std::uint64_t>(r));
}
std::uint64_t OptimizationSpec::selection_seed() const { return mix(verification_seed, 1000); }
std::uint64_t OptimizationSpec::recheck_seed() const { return mix(verification_seed, 2000); }

std::string choice_key_label(const std::string& key, const std::vector<std::string>& keys) {
  // The shortest dotted suffix of the key that no other key shares.
  for (std::size_t pos = key.rfind('.'); pos != std::string::npos && pos > 0; pos = key.rfind('.', pos - 1)) {
    std::string suffix = key.substr(pos + 1);  // not const: returned by move
    const bool unique = std::none_of(keys.begin(), keys.end(), [&](const std::string& k) {
      return k != key && (k == suffix || (k.size() > suffix.size() && k.compare(k.size() - suffix.size() - 1,
                                                                                std::string::npos, "." + suffix) == 0));
    });
    if (unique) return suffix;
  }
  return key;
}

std::string choice_label(const std::map<std::string, std::string>& choice) {
  std::vector<std::string> keys;
  keys.reserve(choice.size());
  for (const auto& [k, v] : choice) keys.push_back(k);
  std::string s;
  for (const auto& [k, v] : choice) s += (s.empty() ? "" : ", ") + choice_key_label(k, keys) + " = " + v;
  return s.empty() ? "-" : s;
}

namespace {

/// [optimization]: the name, the base study (its path into study_path), the search settings.
void read_optimization_table(TomlReader& root, const std::string& path, OptimizationSpec& s, std::string& study_path,
                             std::optional<std::size_t>& replicate_size) {
  TomlReader t = root.table("optimization");
  s.name = t.string("name");
  s.title = t.string("title", "");
  s.notes = t.string("notes", "");
  const std::string study = t.string("study");
  study_path = (fs::path(path).parent_path() / study).lexically_normal().string();
  if (!study.empty() && !fs::exists(study_path)) {
    t.error("study", "\"" + study + "\"", "an existing study file (looked for " + study_path + ")");
    study_path.clear();
  }
  s.samples = static_cast<std::size_t>(t.integer("samples", 2, 100'000'000));
  s.seed = static_cast<std::uint64_t>(t.integer("seed", 0, INT64_MAX));
  const std::string algo = t.choice("algorithm", {"cobyla", "bobyqa", "sbplx", "neldermead", "direct_l", "isres"});
  s.algorithm = parse_algorithm(algo);
  s.max_evaluations = static_cast<int>(t.integer("max_evaluations", 1, 1'000'000));
  s.xtol_rel = t.number(
      "xtol_rel", [](double v) { return v > 0 && v < 1 ? "" : "0 < xtol_rel < 1"; }, 1e-3);
  s.replicates = static_cast<int>(t.integer("replicates", 1, 50, 1));
  s.fast_search = t.choice("search_model", {"full", "fast"}, "full") == "fast";
  if (t.has("replicate_size")) replicate_size = static_cast<std::size_t>(t.integer("replicate_size", 2, 100'000'000));
}

/// [[variable]] and [[choice]] tables.
void read_design_space(TomlReader& root, OptimizationSpec& s) {
  for (auto& v : root.table_array("variable")) {
    DesignVariable d;
    d.parameter = v.string("parameter");
    bool ok1 = true, ok2 = true, ok3 = true;
    auto [lo, u1] = number_and_unit(v, "lower", &ok1);
    auto [hi, u2] = number_and_unit(v, "upper", &ok2);
    auto [st, u3] = number_and_unit(v, "start", &ok3);
    if (ok1 && ok2 && ok3) {
      if (u1 != u2 || u1 != u3)
        v.error("upper", "\"" + u2 + "\"", "lower, upper and start in the same unit (\"" + u1 + "\")");
      if (!(lo < hi)) v.error("upper", value_text(hi, u2), "upper > lower");
      if (!(st >= lo && st <= hi)) v.error("start", value_text(st, u3), "start within [lower, upper]");
    }
    d.unit = u1;
    d.lower = lo;
    d.upper = hi;
    d.start = st;
    s.variables.push_back(d);
  }
  for (auto& c : root.table_array("choice")) {
    Choice ch;
    ch.parameter = c.string("parameter");
    ch.values = c.string_array("values");
    if (ch.values.empty()) c.error("values", "[]", "at least one value");
    s.choices.push_back(ch);
  }
  if (s.variables.empty()) root.error("variable", "", "at least one [[variable]] (a design variable with bounds)");
}

/// [objective]: a statistic of an output, or the sum of variables.
void read_objective(TomlReader& root, OptimizationSpec& s) {
  TomlReader t = root.table("objective");
  if (t.has("variable_sum")) {
    s.variable_sum = t.string_array("variable_sum");
    for (const auto& key : s.variable_sum) {
      if (std::none_of(s.variables.begin(), s.variables.end(), [&](const auto& v) { return v.parameter == key; })) {
        t.error("variable_sum", "\"" + key + "\"", "the parameter of a [[variable]]");
      }
    }
    if (t.has("output")) t.error("output", "", "either output (with statistic) or variable_sum, not both");
  } else {
    s.objective_output = t.string("output");
    s.objective_statistic = t.string("statistic");
    if (!engine::is_statistic(s.objective_statistic)) {
      t.error("statistic", "\"" + s.objective_statistic + "\"", kStatistics);
    }
  }
}

/// One [[constraint]]: output, statistic, limit and the confidence bound it holds at.
Requirement read_constraint(TomlReader& c) {
  Requirement r;
  r.output = c.string("output");
  r.statistic = c.string("statistic");
  const bool stat_ok = engine::is_statistic(r.statistic);
  if (!stat_ok) c.error("statistic", "\"" + r.statistic + "\"", kStatistics);
  if (c.has("at_least")) r.at_least = c.number("at_least");
  if (c.has("at_most")) r.at_most = c.number("at_most");
  if (r.at_least.has_value() == r.at_most.has_value()) c.error("at_least", "", "exactly one of at_least and at_most");
  if (c.has("bound")) {
    const std::string text = c.string("bound");
    try {
      r.bound = parse_bound(text);
    } catch (const Error& e) {
      c.error("bound", "\"" + text + "\"", e.what());
    }
    if (r.bound.side != BoundSide::kNone) {
      if (stat_ok && !bound_supported(r.statistic)) {
        c.error("bound", "\"" + text + "\"",
                "a statistic with a one-sided confidence bound (mean, p<q>, fraction_le:<x>, fraction_ge:<x>); " +
                    r.statistic + " has none on its far side, use a quantile such as p99.73");
      }
      if (r.at_most && r.bound.side != BoundSide::kUpper) {
        c.error("bound", "\"" + text + "\"",
                "an upper bound (\"upper95\") with at_most: the limit must hold at the pessimistic end");
      }
      if (r.at_least && r.bound.side != BoundSide::kLower) {
        c.error("bound", "\"" + text + "\"",
                "a lower bound (\"lower95\") with at_least: the limit must hold at the pessimistic end");
      }
    }
  }
  std::string stat = r.statistic;
  std::replace(stat.begin(), stat.end(), '.', '_');
  std::string default_name = r.output + "." + stat;
  if (r.bound.side != BoundSide::kNone) {
    default_name += '.';
    default_name += to_string(r.bound);
  }
  r.name = c.string("name", default_name);
  return r;
}

/// [pareto], [overrides] and [verification].
void read_pareto_and_verification(TomlReader& root, OptimizationSpec& s) {
  if (root.has("pareto")) {
    TomlReader t = root.table("pareto");
    ParetoSpec p;
    p.output = t.string("output");
    p.statistic = t.string("statistic");
    if (!engine::is_statistic(p.statistic)) t.error("statistic", "\"" + p.statistic + "\"", kStatistics);
    p.points = static_cast<int>(t.integer("points", 0, 50, 3));
    t.string("notes", "");
    s.pareto = p;
  }
  if (root.has("overrides")) {
    TomlReader t = root.table("overrides");
    for (const auto& key : t.keys()) s.overrides[key] = t.string(key);
  }
  if (root.has("verification")) {
    TomlReader t = root.table("verification");
    s.verification_samples = static_cast<std::size_t>(t.integer("samples", 2, 100'000'000));
    s.verification_seed = static_cast<std::uint64_t>(t.integer("seed", 0, INT64_MAX));
    if (t.has("equivalence_margin")) {
      const std::string text = t.string("equivalence_margin");
      std::istringstream in(text);
      double v = NAN;
      in >> v;
      std::string rest;
      std::getline(in >> std::ws, rest);
      if (!std::isfinite(v) || v <= 0 || !(rest.empty() || rest == "%")) {
        t.error("equivalence_margin", "\"" + text + "\"",
                "a positive share of the better choice's figure (\"5%\") or a positive number in the objective's unit");
      } else {
        s.equivalence_relative = rest == "%";
        s.equivalence_margin = s.equivalence_relative ? v / 100.0 : v;
        s.equivalence_margin_text = text;
      }
    }
    s.max_nearest_rounds = static_cast<int>(t.integer("max_nearest_rounds", 0, 20, 3));
  }
}

/// The base study loaded, the replicate layout and every output the file names checked
/// against it (all errors at once).
void check_against_study(OptimizationSpec& s, const std::string& path, const std::string& study_path,
                         const std::optional<std::size_t>& replicate_size) {
  s.base = engine::load_study(study_path);
  try {  // the declared units of the base study's outputs (an invalid model is reported below)
    for (const auto& o : engine::study_kind(s.base.kind).outputs(s.base)) s.output_units[o.name] = o.unit;
  } catch (const engine::ValidationError&) {
  }
  std::vector<InputError> errors;
  if (s.fast_search) {
    s.fast_model_text = engine::study_kind(s.base.kind).fast_model(s.base);
    if (s.fast_model_text.empty()) {
      errors.emplace_back(SourceLocation{path, 0, 0}, "optimization.search_model", "\"fast\"",
                          "\"full\": the kind '" + s.base.kind + "' of " + study_path + " has no fast model");
    }
  }
  if (replicate_size) s.base.replicate_size = *replicate_size;
  if (const std::size_t m = s.base.replicate_size; m > 0) {
    const std::string where = replicate_size ? "optimization.replicate_size" : "replicate_size (of " + study_path + ")";
    if (s.base.method == sampling::SamplingMethod::kSobol && (m & (m - 1)) != 0) {
      errors.emplace_back(SourceLocation{path, 0, 0}, where, std::to_string(m), "a power of two for a sobol design");
    }
    for (auto [n, key] :
         {std::pair{s.samples, "optimization.samples"}, std::pair{s.verification_samples, "verification.samples"}}) {
      if (n % m != 0 || n / m < 2) {
        errors.emplace_back(SourceLocation{path, 0, 0}, key, std::to_string(n),
                            "a multiple of the replicate size " + std::to_string(m) + ", at least 2 replicates");
      }
    }
  }
  std::map<std::string, std::string> start;
  for (const auto& v : s.variables) start[v.parameter] = value_text(v.start, v.unit);
  for (const auto& c : s.choices) start[c.parameter] = c.values.front();
  engine::StudyConfig base = s.base;
  for (const auto& [k, v] : s.overrides) base.overrides[k] = v;
  for (const auto& [k, v] : start) base.overrides[k] = v;
  const std::vector<std::string> names = engine::study_output_names(base);
  auto check_output = [&](const std::string& output, const std::string& key) {
    if (std::find(names.begin(), names.end(), output) == names.end()) {
      std::string all;
      for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
      errors.emplace_back(SourceLocation{path, 0, 0}, key, "\"" + output + "\"",
                          "an output of " + study_path + ": " + all);
    }
  };
  if (!s.objective_output.empty()) check_output(s.objective_output, "objective.output");
  if (s.pareto) check_output(s.pareto->output, "pareto.output");
  for (std::size_t i = 0; i < s.constraints.size(); ++i) {
    check_output(s.constraints[i].output, "constraint[" + std::to_string(i) + "].output");
  }
  if (!errors.empty()) throw engine::ValidationError(errors);
}

}  // namespace

OptimizationSpec load_optimization(const std::string& path) {
  toml::table doc = engine::parse_toml_file(path);
  auto ctx = std::make_shared<engine::ReadContext>();
  ctx->file = path;
  TomlReader root(doc, ctx);
  OptimizationSpec s;
  s.file = path;
  std::string study_path;
  std::optional<std::size_t> replicate_size;
  read_optimization_table(root, path, s, study_path, replicate_size);
  read_design_space(root, s);
  read_objective(root, s);
  for (auto& c : root.table_array("constraint")) s.constraints.push_back(read_constraint(c));
  read_pareto_and_verification(root, s);
  engine::finish(doc, *ctx);
  check_against_study(s, path, study_path, replicate_size);
  return s;
}

}  // namespace poise::optimize
