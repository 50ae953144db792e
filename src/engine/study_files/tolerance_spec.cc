#include "engine/study_files/tolerance_spec.h"

namespace poise::engine {

namespace {

// deviation = [lower, upper]: two values of `dim` (plain numbers when dimensionless), lower < upper.
std::pair<double, double> read_deviation(TomlReader& t, const units::Dimension& dim) {
  const std::vector<std::string> ends = t.string_array("deviation");
  const std::string expected = "two deviations [lower, upper] from the value, e.g. [\"0 mm\", \"+0.06 mm\"]";
  if (ends.size() != 2) {
    t.error("deviation", std::to_string(ends.size()) + " values", expected);
    return {0.0, 0.0};
  }
  double x[2] = {0.0, 0.0};
  for (int k = 0; k < 2; ++k) {
    try {
      x[k] = units::parse_as(ends[k], dim);
    } catch (const Error& e) {
      t.error("deviation", quote_value(ends[k]), expected + " (" + e.what() + ")");
      return {0.0, 0.0};
    }
  }
  if (!(x[0] < x[1]))
    t.error("deviation", "[" + ends[0] + ", " + ends[1] + "]", "the lower deviation first, below the upper");
  return {x[0], x[1]};
}

}  // namespace

ToleranceSpec read_tolerance(TomlReader& parent, const std::string& key, const units::Dimension& dim,
                             const std::string& display_unit) {
  ToleranceSpec spec;
  spec.display_unit = display_unit;
  spec.display_factor = display_unit.empty() ? 1.0 : units::unit_factor(display_unit);
  TomlReader t = parent.table(key);
  const std::size_t errors_before = t.context().errors.size();
  spec.source = t.string("source", "");
  const std::string kind_name = t.choice("distribution", {"normal", "uniform", "arcsine", "truncated_normal", "fixed"});
  const auto kind = sampling::parse_distribution_kind(kind_name);
  const bool dimensionless = dim == units::kDimensionless;
  double nominal = 0.0, tol = 0.0;
  auto convention = sampling::ToleranceConvention::kBounds;
  if (t.schema_only()) {  // `poise keys`: both forms of a tolerance, neither required alone
    const std::string value =
        dimensionless ? std::string("a plain number (no unit)")
                      : units::dimension_name(dim) + " with its unit, e.g. \"1 " + units::example_unit(dim) + "\"";
    t.ask("tolerance", value + "; a deviation from the value, with tolerance_is (or give min and max instead)",
          "(optional)", false);
    t.ask("tolerance_is", "one of \"bounds\" | \"1sigma\" | \"2sigma\" | \"3sigma\" (with tolerance)", "(optional)",
          false);
    t.ask("min", value + "; with max, the range itself (instead of tolerance)", "(optional)", false);
    t.ask("max", value + "; with min", "(optional)", false);
    if (dimensionless) {
      t.number("min");
      t.number("max");
    } else {
      t.quantity("min", dim);
      t.quantity("max", dim);
    }
  }
  if (t.schema_only()) {
    t.ask("deviation",
          "two values [lower, upper] deviations from the value, e.g. [\"0 mm\", \"+0.06 mm\"] (a drawing's "
          "asymmetric limits), with tolerance_is; instead of tolerance",
          "(optional)", false);
  }
  if (t.has("deviation") && !t.schema_only()) {
    // A drawing's asymmetric limits: the distribution centred between them, its half-width
    // read by tolerance_is.
    const auto range = read_deviation(t, dim);
    if (t.has("tolerance") || t.has("min") || t.has("max")) {
      t.error("deviation", "", "either deviation, tolerance or min/max, not two of them");
    }
    nominal = 0.5 * (range.first + range.second);
    tol = 0.5 * (range.second - range.first);
    convention = sampling::parse_convention(t.choice("tolerance_is", {"bounds", "1sigma", "2sigma", "3sigma"}));
  } else if (t.has("min") || t.has("max")) {
    const double lo = dimensionless ? t.number("min") : t.quantity("min", dim);
    const double hi = dimensionless ? t.number("max") : t.quantity("max", dim);
    if (hi < lo) t.error("max", "", "max >= min");
    if (t.has("tolerance")) t.error("tolerance", "", "either tolerance or min/max, not both");
    if (t.has("tolerance_is")) {
      t.error("tolerance_is", "", "no tolerance_is with min/max (min/max are bounds)");
    }
    nominal = 0.5 * (lo + hi);
    tol = 0.5 * (hi - lo);
  } else {
    tol = dimensionless ? t.number("tolerance", non_negative) : t.quantity("tolerance", dim, non_negative);
    const std::string conv = t.choice("tolerance_is", {"bounds", "1sigma", "2sigma", "3sigma"});
    convention = sampling::parse_convention(conv);
  }
  spec.tolerance = tol;
  // A refused distribution, tolerance or bound is reported once, not again as a distribution
  // built from the stand-in values.
  if (t.context().errors.size() != errors_before) return spec;
  try {
    spec.dist = sampling::Distribution(kind, nominal, tol, convention);
  } catch (const Error& e) {
    t.error("distribution", "\"" + kind_name + "\" with tolerance_is \"" + sampling::to_string(convention) + "\"",
            e.what());
  }
  return spec;
}

ScopedTolerance read_scoped_tolerance(TomlReader& parent, const std::string& key, const units::Dimension& dim,
                                      const std::string& display_unit) {
  ScopedTolerance t;
  t.spec = read_tolerance(parent, key, dim, display_unit);
  TomlReader sub = parent.table(key);
  t.per_test = sub.choice("scope", {"unit", "test"}) == "test";
  return t;
}

}  // namespace poise::engine
