#include "engine/run/stack_up.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <boost/math/distributions/chi_squared.hpp>

#include "core/error.h"
#include "core/format.h"
#include "engine/results/result_io.h"
#include "engine/results/specification_limits.h"

namespace poise::engine {
namespace {
using nlohmann::json;

constexpr std::size_t kMostCornerInputs = 16;  // 65,536 corners

// The outputs at inputs x (the study's units), or nullopt where the point has no value.
std::optional<std::vector<double>> outputs_at(const ProcedureStudy& study, const std::vector<double>& x) {
  std::vector<double> y(study.outputs().size());
  try {
    study.evaluate_point(0, x, y);
  } catch (const Error&) {
    return std::nullopt;
  }
  for (double v : y) {
    if (!std::isfinite(v)) return std::nullopt;
  }
  return y;
}

// d output_k / d input_i at x by central differences (one-sided where one side has no value;
// NaN where neither has).
std::vector<std::vector<double>> sensitivities(const ProcedureStudy& study, const std::vector<double>& x,
                                               const std::vector<double>& half, const std::vector<double>& f) {
  std::vector<std::vector<double>> c(f.size(), std::vector<double>(x.size(), 0.0));
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!(half[i] > 0.0)) continue;
    const double h = 1e-3 * half[i];
    std::vector<double> up = x, down = x;
    up[i] += h;
    down[i] -= h;
    const auto fu = outputs_at(study, up), fd = outputs_at(study, down);
    for (std::size_t k = 0; k < f.size(); ++k) {
      c[k][i] = fu && fd ? ((*fu)[k] - (*fd)[k]) / (2.0 * h)
                : fu     ? ((*fu)[k] - f[k]) / h
                : fd     ? (f[k] - (*fd)[k]) / h
                         : std::numeric_limits<double>::quiet_NaN();
    }
  }
  return c;
}

// Each output's least and greatest value over the box's corners, and the corners without a value;
// the corners go to the study in batches (one call of a program per batch, not per corner).
struct Corners {
  std::vector<double> lo, hi;
  std::size_t failed = 0;
};
Corners corner_extremes(const ProcedureStudy& study, const std::vector<InputLimits>& limits, std::size_t q) {
  Corners c{std::vector<double>(q, std::numeric_limits<double>::infinity()),
            std::vector<double>(q, -std::numeric_limits<double>::infinity()), 0};
  const std::size_t n = limits.size(), corners = std::size_t{1} << n, batch = 4096;
  std::vector<double> x, y;
  std::vector<std::string> failures;
  for (std::size_t first = 0; first < corners; first += batch) {
    const std::size_t rows = std::min(batch, corners - first);
    x.resize(rows * n);
    y.assign(rows * q, 0.0);
    for (std::size_t r = 0; r < rows; ++r) {
      for (std::size_t i = 0; i < n; ++i) x[r * n + i] = ((first + r) >> i) & 1U ? limits[i].upper : limits[i].lower;
    }
    study.evaluate_points(x, rows, y, failures);
    for (std::size_t r = 0; r < rows; ++r) {
      bool ok = failures[r].empty();
      for (std::size_t k = 0; k < q && ok; ++k) ok = std::isfinite(y[r * q + k]);
      if (!ok) {
        ++c.failed;
        continue;
      }
      for (std::size_t k = 0; k < q; ++k) {
        c.lo[k] = std::min(c.lo[k], y[r * q + k]);
        c.hi[k] = std::max(c.hi[k], y[r * q + k]);
      }
    }
  }
  return c;
}

json percent_shares(const std::vector<double>& w) {
  double total = 0.0;
  for (double v : w) total += v;
  json out = json::array();
  for (double v : w) out.push_back(total > 0.0 ? json(100.0 * v / total) : json(nullptr));
  return out;
}

// Cp, Cpk and ppm outside [lsl, usl] with their 95% intervals.
json capability(const Requirement& r, const OutputSpec& o, std::size_t k, const McResult& mc) {
  const auto [lsl, usl] = specification_limits(r, o.unit);
  const sampling::Summary& s = mc.outputs[k];
  const double n = static_cast<double>(s.n), sd = s.std.value, mean = s.mean.value;
  json j{{"lower", lsl}, {"upper", usl}, {"unit", o.unit}, {"as_written", r.within}};
  if (n > 2 && sd > 0.0) {
    const double cp = (usl - lsl) / (6.0 * sd);
    const boost::math::chi_squared chi(n - 1.0);
    j["cp"] = {{"value", cp},
               {"ci95",
                {cp * std::sqrt(boost::math::quantile(chi, 0.025) / (n - 1.0)),
                 cp * std::sqrt(boost::math::quantile(chi, 0.975) / (n - 1.0))}}};
    const double cpk = std::min(usl - mean, mean - lsl) / (3.0 * sd);
    j["cpk"] = {{"value", cpk}, {"ci95", {cpk_bound(cpk, s.n, 0.975, false), cpk_bound(cpk, s.n, 0.975, true)}}};
  }
  // Parts per million outside, the failed samples counted outside, as the verdict of a
  // ppm_at_most requirement counts them: its one-sided bounds at 97.5% are the 95% interval.
  Requirement ppm = r;
  ppm.statistic = "ppm";
  ppm.at_most = true;
  ppm.confidence = 0.975;
  const OutputValues values{
      .values = &mc.values[k], .ok_index = &mc.ok_index, .replicate_size = 0, .failed = mc.failures};
  const SpecificationFigure f = specification_figure(ppm, values, lsl, usl);
  j["ppm_outside"] = {{"value", f.value},
                      {"ci95", {f.other ? json(*f.other) : json(nullptr), f.bound ? json(*f.bound) : json(nullptr)}}};
  j["note"] = "Cp and Cpk assume normal values; ppm is counted on the samples (failed ones outside)";
  return j;
}

// The figures of output k.
json output_figures(std::size_t k, const std::vector<InputLimits>& limits, const std::vector<double>& f_mean,
                    const std::vector<double>& f_centre, const std::vector<std::vector<double>>& c,
                    const std::optional<Corners>& corners, const McResult& mc) {
  double wc = 0.0, rss2 = 0.0, sd2 = 0.0;
  std::vector<double> wc_share, rss_share;
  for (std::size_t i = 0; i < limits.size(); ++i) {
    const double h = 0.5 * (limits[i].upper - limits[i].lower);
    wc += std::abs(c[k][i]) * h;
    rss2 += c[k][i] * c[k][i] * h * h;
    sd2 += c[k][i] * c[k][i] * limits[i].sd * limits[i].sd;
    wc_share.push_back(std::abs(c[k][i]) * h);
    rss_share.push_back(c[k][i] * c[k][i] * limits[i].sd * limits[i].sd);
  }
  json o{{"nominal", f_mean[k]},
         {"centre", f_centre[k]},
         {"sensitivities", c[k]},
         {"worst_case_linear", {{"min", f_centre[k] - wc}, {"max", f_centre[k] + wc}, {"half_width", wc}}},
         {"rss",
          {{"min", f_centre[k] - std::sqrt(rss2)},
           {"max", f_centre[k] + std::sqrt(rss2)},
           {"half_width", std::sqrt(rss2)},
           {"sd_first_order", std::sqrt(sd2)}}}};
  if (corners) {
    o["worst_case"] = {{"min", corners->lo[k]},
                       {"max", corners->hi[k]},
                       {"corners", std::size_t{1} << limits.size()},
                       {"corners_without_value", corners->failed}};
  }
  if (k < mc.outputs.size()) {
    const sampling::Summary& s = mc.outputs[k];
    o["monte_carlo"] = {{"mean", s.mean.value},     {"sd", s.std.value},          {"min", s.min.value},
                        {"p0_135", s.p0_135.value}, {"p99_865", s.p99_865.value}, {"max", s.max.value}};
  }
  json shares{{"worst_case", percent_shares(wc_share)}, {"rss", percent_shares(rss_share)}};
  if (const auto mc_shares = mc.moments.variance_shares(k)) {
    json pct = json::array();
    for (double v : mc_shares->src2) pct.push_back(100.0 * v);
    shares["monte_carlo"] = pct;
    shares["monte_carlo_r2"] = mc_shares->r2;
  }
  o["contributions_percent"] = shares;
  return o;
}

}  // namespace

json stack_up_json(const ProcedureStudy& study, const McResult& mc, const std::vector<Requirement>& requirements) {
  if (!study.evaluates_inputs() || study.has_own_randomness()) return nullptr;
  const std::vector<InputLimits> limits = study.input_limits();
  if (limits.empty()) return nullptr;
  std::vector<double> centre, mean, half;
  json inputs = json::array();
  for (std::size_t i = 0; i < limits.size(); ++i) {
    centre.push_back(0.5 * (limits[i].lower + limits[i].upper));
    half.push_back(0.5 * (limits[i].upper - limits[i].lower));
    mean.push_back(limits[i].mean);
    inputs.push_back({{"name", study.input_names()[i]},
                      {"lower", limits[i].lower},
                      {"upper", limits[i].upper},
                      {"mean", limits[i].mean},
                      {"sd", limits[i].sd}});
  }
  const auto f_centre = outputs_at(study, centre), f_mean = outputs_at(study, mean);
  if (!f_centre || !f_mean) return nullptr;
  const auto c = sensitivities(study, centre, half, *f_centre);
  std::optional<Corners> corners;
  // The corners, unless there are more of them than the run's samples (and 4096): a slow model's
  // worst case must not cost more than its Monte Carlo.
  const std::size_t corner_budget = std::max<std::size_t>(4096, mc.n);
  if (limits.size() <= kMostCornerInputs && (std::size_t{1} << limits.size()) <= corner_budget) {
    corners = corner_extremes(study, limits, f_centre->size());
  }
  json outputs = json::object();
  const auto& specs = study.outputs();
  for (std::size_t k = 0; k < specs.size(); ++k) {
    json o = output_figures(k, limits, *f_mean, *f_centre, c, corners, mc);
    o["unit"] = specs[k].unit;
    for (const Requirement& r : requirements) {
      if (r.output == specs[k].name && !r.within.empty() && k < mc.outputs.size() && !o.contains("capability")) {
        o["capability"] = capability(r, specs[k], k, mc);
      }
    }
    outputs[specs[k].name] = o;
  }
  return {{"inputs", inputs},
          {"outputs", outputs},
          {"worst_case_method",
           corners ? "the extremes over the 2^n corners of the box of drawing limits (exact for an output monotone in "
                     "each input), beside the linearised bound"
                   : "linearised only: more corners (2^n) than 65536 or than the run's samples"},
          {"rss_method", "first order at the box's centre: -+ sqrt(sum (c_i h_i)^2) of the tolerances as written"},
          {"monte_carlo_contributions",
           "squared standardized regression coefficients of the run's samples (their sum, R^2, is 1 for a linear "
           "output)"}};
}

}  // namespace poise::engine
