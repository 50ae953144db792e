#include "engine/results/specification_limits.h"

#include <cmath>
#include <limits>
#include <numeric>

#include <boost/math/distributions/normal.hpp>

#include "core/error.h"
#include "core/format.h"
#include "core/units.h"
#include "engine/kind_interface/study_kind.h"
#include "engine/results/confidence_bound.h"
#include "engine/results/result_io.h"
#include "engine/study_files/toml_reader.h"

namespace poise::engine {
namespace {

struct FigureKey {
  const char* key;        // the key of the study file
  const char* statistic;  // the requirement's statistic
  bool at_most;
};
constexpr FigureKey kFigures[] = {
    {"yield_at_least", "yield", false}, {"ppm_at_most", "ppm", true}, {"cpk_at_least", "cpk", false}};

std::string figure_check(const std::string& statistic, double x) {
  if (statistic == "yield") return x > 0.0 && x < 1.0 ? "" : "a share of units, 0 < yield < 1, e.g. 0.9973";
  if (statistic == "ppm") return x >= 0.0 && x < 1e6 ? "" : "parts per million, 0 <= ppm < 1000000, e.g. 2700";
  return x > 0.0 ? "" : "a capability index > 0, e.g. 1.33";
}

}  // namespace

bool is_specification_statistic(const std::string& statistic) {
  return statistic == "yield" || statistic == "ppm" || statistic == "cpk";
}

void read_specification(TomlReader& t, Requirement& r) {
  if (t.schema_only()) {
    t.ask("within",
          "two values with the output's unit, [lower, upper] specification limits, e.g. [\"0.05 mm\", "
          "\"0.80 mm\"], with one of yield_at_least, ppm_at_most or cpk_at_least (instead of statistic and at_most)",
          "", false);
    for (const FigureKey& f : kFigures) t.ask(f.key, "a number (with within)", "", false);
    return;
  }
  r.within = t.string_array("within");
  if (r.within.size() != 2) {
    t.error("within", std::to_string(r.within.size()) + " values",
            "two values with the output's unit: [lower, upper], e.g. [\"0.05 mm\", \"0.80 mm\"]");
    r.within.resize(2);
  }
  for (const char* k : {"statistic", "at_most", "at_least"}) {
    if (t.has(k)) {
      t.error(k, "", std::string("no ") + k + " beside within: yield_at_least, ppm_at_most or cpk_at_least says what");
    }
  }
  std::vector<const FigureKey*> given;
  for (const FigureKey& f : kFigures) {
    if (t.has(f.key)) given.push_back(&f);
  }
  if (given.size() != 1) {
    t.error(given.empty() ? "yield_at_least" : given[1]->key, "",
            "exactly one of yield_at_least (e.g. 0.9973), ppm_at_most (e.g. 2700) or cpk_at_least (e.g. 1.33) "
            "with within");
    if (given.empty()) return;
  }
  const FigureKey& f = *given[0];
  r.statistic = f.statistic;
  r.at_most = f.at_most;
  const std::string statistic = f.statistic;
  const double x = t.number(f.key, [&](double v) { return figure_check(statistic, v); });
  r.limit_text = format_significant(x, 10);
  if (statistic == "ppm") r.limit_text += " ppm";
  double lower = 0.0, upper = 0.0;
  try {
    lower = units::parse_quantity(r.within[0]).value;
    upper = units::parse_quantity(r.within[1]).value;
  } catch (const Error& e) {
    t.error("within", "[" + quote_value(r.within[0]) + ", " + quote_value(r.within[1]) + "]",
            std::string("two numbers with the output's unit, e.g. [\"0.05 mm\", \"0.80 mm\"] (") + e.what() + ")");
    return;
  }
  if (!(lower < upper)) {
    t.error("within", "[" + quote_value(r.within[0]) + ", " + quote_value(r.within[1]) + "]",
            "the lower limit first, below the upper one");
  }
}

std::pair<double, double> specification_limits(const Requirement& r, const std::string& unit) {
  const double f = unit_quantity(unit).value;
  return {units::parse_quantity(r.within[0]).value / f, units::parse_quantity(r.within[1]).value / f};
}

double cpk_bound(double cpk, std::size_t n, double confidence, bool upper) {
  const double nn = static_cast<double>(n);
  const double z = boost::math::quantile(boost::math::normal(), confidence);
  const double se = std::sqrt(1.0 / (9.0 * nn) + cpk * cpk / (2.0 * (nn - 1.0)));
  return upper ? cpk + z * se : cpk - z * se;
}

SpecificationFigure specification_figure(const Requirement& r, const OutputValues& ov, double lower, double upper) {
  SpecificationFigure out;
  const std::vector<double>& v = *ov.values;
  const BoundSpec up{BoundSide::kUpper, r.confidence}, down{BoundSide::kLower, r.confidence};
  if (r.statistic == "cpk") {
    const double n = static_cast<double>(v.size());
    const double mean = std::accumulate(v.begin(), v.end(), 0.0) / n;
    double ss = 0.0;
    for (double x : v) ss += (x - mean) * (x - mean);
    const double sd = v.size() > 1 ? std::sqrt(ss / (n - 1.0)) : 0.0;
    out.value = sd > 0.0 ? std::min(upper - mean, mean - lower) / (3.0 * sd) : std::numeric_limits<double>::infinity();
    if (v.size() > 2 && std::isfinite(out.value)) {
      out.bound = cpk_bound(out.value, v.size(), r.confidence, false);
      out.other = cpk_bound(out.value, v.size(), r.confidence, true);
    }
    out.note = "Cpk assumes normal values (its bound is Bissell's normal approximation)";
    if (ov.failed > 0) out.note += "; the " + std::to_string(ov.failed) + " failed samples have no value to enter it";
    return out;
  }
  // The share within the limits, the failed samples counted as outside (NaN is not within).
  SampleSet set = sample_set(v, *ov.ok_index, ov.replicate_size);
  if (set.replicate.empty()) set.values.insert(set.values.end(), ov.failed, std::numeric_limits<double>::quiet_NaN());
  const std::string within = "fraction_within:" + format_significant(lower, 17) + ":" + format_significant(upper, 17);
  const double share = statistic(set.values, within);
  const std::optional<double> lo = one_sided_bound(set, within, down), hi = one_sided_bound(set, within, up);
  if (r.statistic == "yield") {
    out = {share, lo, hi, ""};
  } else {  // ppm outside: the yield's bounds, mirrored
    const auto ppm = [](std::optional<double> y) { return y ? std::optional<double>(1e6 * (1.0 - *y)) : std::nullopt; };
    out = {1e6 * (1.0 - share), ppm(lo), ppm(hi), ""};
  }
  if (ov.failed > 0) {
    out.note = std::to_string(ov.failed) + " failed samples counted as outside the limits";
    if (!set.replicate.empty()) out.note = std::to_string(ov.failed) + " failed samples left out of the replicates";
  }
  return out;
}

}  // namespace poise::engine
