#include "models/seeker_los_budget.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/units.h"
#include "models/seeker_los_chain.h"

namespace poise::models {
namespace {

using units::kArcsecPerRad;
constexpr double kSqrt2 = 1.41421356237309504880;
constexpr double kSqrt3 = 1.73205080756887729353;

struct AxisTerms {
  double perpendicularity, runout_rss, wobble_min, wobble_max, random_wobble, total_min, total_max;
};

AxisTerms axis_terms(const WangBudgetAxisInputs& a, double k_min, double k_max) {
  AxisTerms t{};
  t.perpendicularity = a.perpendicularity / a.span * kArcsecPerRad;
  t.runout_rss = std::sqrt(a.radial_runout * a.radial_runout + a.face_runout * a.face_runout +
                           a.clearance * a.clearance + a.bore_roundness * a.bore_roundness);
  t.wobble_min = k_min * t.runout_rss / a.span * kArcsecPerRad / kSqrt3;
  t.wobble_max = k_max * t.runout_rss / a.span * kArcsecPerRad / kSqrt3;
  const double r1 = a.ball_roundness / (kSqrt2 * a.span) * kArcsecPerRad;
  const double r2 = a.seat_deformation / (kSqrt2 * a.span) * kArcsecPerRad;
  t.random_wobble = std::sqrt(r1 * r1 + r2 * r2);
  auto rss = [&](double w) {
    return std::sqrt(t.perpendicularity * t.perpendicularity + w * w + t.random_wobble * t.random_wobble);
  };
  t.total_min = rss(t.wobble_min);
  t.total_max = rss(t.wobble_max);
  return t;
}

void check_axis(const WangBudgetAxisInputs& a, const char* name) {
  require(a.span > 0, std::string(name) + " bearing span must be positive");
}

struct PointFigures {
  double eq8, rss, gc;
};

// The paper's propagation at one gimbal angle (a, b) for axis totals d1, d2, d3 (arcsec).
PointFigures point_figures(double d1, double d2, double d3, double a, double b) {
  const double da1 = d1 * std::tan(b) * std::sin(a), da2 = d2 * std::tan(b), da3 = d3 / std::cos(b);
  const double da2sum = da1 * da1 + da2 * da2 + da3 * da3;
  const double db = d1 * std::cos(a);
  const double w = a * a + b * b;
  PointFigures f;
  f.eq8 = w > 0 ? std::sqrt((a * a * da2sum + b * b * db * db) / w) : NAN;  // 0/0 at a = b = 0
  f.rss = std::sqrt(da2sum + db * db);
  f.gc = std::sqrt(da2sum * std::cos(b) * std::cos(b) + db * db);
  return f;
}

}  // namespace

WangGridFigures wang_grid_figures(double d1_min, double d1_max, double d2_min, double d2_max, double d3,
                                  const WangBudgetInputs& in) {
  const auto alpha = linspace(in.alpha_min, in.alpha_max, in.grid_points);
  const auto beta = linspace(in.beta_min, in.beta_max, in.grid_points);
  const double inf = std::numeric_limits<double>::infinity();
  WangGridFigures g{inf, 0, inf, 0, inf, 0};
  for (double a : alpha) {
    for (double b : beta) {
      const PointFigures lo = point_figures(d1_min, d2_min, d3, a, b);
      const PointFigures hi = point_figures(d1_max, d2_max, d3, a, b);
      if (std::isfinite(lo.eq8)) g.eq8_min = std::min(g.eq8_min, lo.eq8);
      if (std::isfinite(hi.eq8)) g.eq8_max = std::max(g.eq8_max, hi.eq8);
      g.rss_min = std::min(g.rss_min, lo.rss);
      g.rss_max = std::max(g.rss_max, hi.rss);
      g.gc_min = std::min(g.gc_min, lo.gc);
      g.gc_max = std::max(g.gc_max, hi.gc);
    }
  }
  return g;
}

const BudgetTerm& WangBudget::term(const std::string& key) const {
  for (const auto& t : terms) {
    if (t.key == key) return t;
  }
  throw Error("no budget term \"" + key + "\"");
}

WangBudget compute_wang_budget(const WangBudgetInputs& in) {
  check_axis(in.yaw, "yaw");
  check_axis(in.pitch, "pitch");
  require(in.barrel_length > 0, "optical barrel length must be positive");
  require(in.pixel_ifov > 0, "pixel IFOV must be positive");
  require(in.k_min <= in.k_max, "load-deformation factor: k_min must not exceed k_max");
  require(in.grid_points >= 2, "budget grid needs at least 2 points per axis");

  const AxisTerms y = axis_terms(in.yaw, in.k_min, in.k_max);
  const AxisTerms p = axis_terms(in.pitch, in.k_min, in.k_max);
  const double d3 = in.optical_axis_error / in.barrel_length * kArcsecPerRad / kSqrt3;

  WangBudget b;
  auto add = [&](std::string key, std::string desc, std::string eq, double v, std::string unit) {
    b.terms.push_back({std::move(key), std::move(desc), std::move(eq), v, std::move(unit)});
  };
  add("sigma_11", "yaw axis perpendicularity to base", "Eq. 1", y.perpendicularity, "arcsec");
  add("delta_16", "yaw run-out RSS (radial, face, clearance, bore)", "Sec. 2.1.1 (3)", y.runout_rss * 1e3, "mm");
  add("sigma_12_min", "yaw wobble, k' = k_min", "Eq. 2", y.wobble_min, "arcsec");
  add("sigma_12_max", "yaw wobble, k' = k_max", "Eq. 2", y.wobble_max, "arcsec");
  add("sigma_13", "yaw random wobble (ball roundness, seat deformation)", "Eq. 3", y.random_wobble, "arcsec");
  add("delta_1_min", "yaw shafting total, k' = k_min", "Sec. 2.1.1", y.total_min, "arcsec");
  add("delta_1_max", "yaw shafting total, k' = k_max", "Sec. 2.1.1", y.total_max, "arcsec");
  add("sigma_21", "pitch axis perpendicularity to yaw axis", "Eq. 4", p.perpendicularity, "arcsec");
  add("delta_26", "pitch run-out RSS", "Sec. 2.1.2 (2)", p.runout_rss * 1e3, "mm");
  add("sigma_22_min", "pitch wobble, k' = k_min", "Eq. 5", p.wobble_min, "arcsec");
  add("sigma_22_max", "pitch wobble, k' = k_max", "Eq. 5", p.wobble_max, "arcsec");
  add("sigma_23", "pitch random wobble", "Eq. 6", p.random_wobble, "arcsec");
  add("delta_2_min", "pitch shafting total, k' = k_min", "Sec. 2.1.2", p.total_min, "arcsec");
  add("delta_2_max", "pitch shafting total, k' = k_max", "Sec. 2.1.2", p.total_max, "arcsec");
  add("delta_3", "optical axis to pitch axis", "Eq. 7", d3, "arcsec");

  b.alpha = linspace(in.alpha_min, in.alpha_max, in.grid_points);
  b.beta = linspace(in.beta_min, in.beta_max, in.grid_points);
  b.eq8_map_kmax.assign(b.alpha.size() * b.beta.size(), 0.0);
  b.great_circle_map_kmax.assign(b.eq8_map_kmax.size(), 0.0);
  b.rss_map_kmax.assign(b.eq8_map_kmax.size(), 0.0);
  for (std::size_t ia = 0; ia < b.alpha.size(); ++ia) {
    for (std::size_t ib = 0; ib < b.beta.size(); ++ib) {
      const PointFigures f = point_figures(y.total_max, p.total_max, d3, b.alpha[ia], b.beta[ib]);
      b.eq8_map_kmax[ia * b.beta.size() + ib] = f.eq8;
      b.great_circle_map_kmax[ia * b.beta.size() + ib] = f.gc;
      b.rss_map_kmax[ia * b.beta.size() + ib] = f.rss;
    }
  }
  const WangGridFigures g = wang_grid_figures(y.total_min, y.total_max, p.total_min, p.total_max, d3, in);
  const double px = in.pixel_ifov * kArcsecPerRad;
  add("los_min", "LOS error sqrt(Da^2 + Db^2), least over the field, k' = k_min", "Sec. 3", g.rss_min, "arcsec");
  add("los_max", "LOS error sqrt(Da^2 + Db^2), greatest over the field, k' = k_max", "Sec. 3", g.rss_max, "arcsec");
  add("los_min_px", "least LOS error in pixels", "Sec. 3", g.rss_min / px, "px");
  add("los_max_px", "greatest LOS error in pixels", "Sec. 3", g.rss_max / px, "px");
  add("los_eq8_min", "LOS error by Eq. 8 as printed, least over the field, k' = k_min", "Eq. 8", g.eq8_min, "arcsec");
  add("los_eq8_max", "LOS error by Eq. 8 as printed, greatest over the field, k' = k_max", "Eq. 8", g.eq8_max,
      "arcsec");
  add("los_gc_min", "angle true-nominal LOS sqrt((Da cos b)^2 + Db^2), least, k' = k_min", "corrected Eq. 8", g.gc_min,
      "arcsec");
  add("los_gc_max", "angle true-nominal LOS sqrt((Da cos b)^2 + Db^2), greatest, k' = k_max", "corrected Eq. 8",
      g.gc_max, "arcsec");
  add("los_gc_max_px", "greatest angle true-nominal LOS in pixels", "corrected Eq. 8", g.gc_max / px, "px");
  return b;
}

}  // namespace poise::models
