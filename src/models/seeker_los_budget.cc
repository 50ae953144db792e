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
    return std::sqrt(t.perpendicularity * t.perpendicularity + w * w +
                     t.random_wobble * t.random_wobble);
  };
  t.total_min = rss(t.wobble_min);
  t.total_max = rss(t.wobble_max);
  return t;
}

void check_axis(const WangBudgetAxisInputs& a, const char* name) {
  require(a.span > 0, std::string(name) + " bearing span must be positive");
}

struct GridExtremes {
  double eq8_min = std::numeric_limits<double>::infinity(), eq8_max = 0;
  double gc_min = std::numeric_limits<double>::infinity(), gc_max = 0;
};

}  // namespace

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
  add("delta_16", "yaw run-out RSS (radial, face, clearance, bore)", "Sec. 2.1.1 (3)",
      y.runout_rss * 1e3, "mm");
  add("sigma_12_min", "yaw wobble, k' = k_min", "Eq. 2", y.wobble_min, "arcsec");
  add("sigma_12_max", "yaw wobble, k' = k_max", "Eq. 2", y.wobble_max, "arcsec");
  add("sigma_13", "yaw random wobble (ball roundness, seat deformation)", "Eq. 3",
      y.random_wobble, "arcsec");
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
  GridExtremes lo_k, hi_k;
  b.eq8_map_kmax.assign(b.alpha.size() * b.beta.size(), 0.0);
  b.great_circle_map_kmax.assign(b.eq8_map_kmax.size(), 0.0);
  for (int pass = 0; pass < 2; ++pass) {
    const double d1 = pass == 0 ? y.total_min : y.total_max;
    const double d2 = pass == 0 ? p.total_min : p.total_max;
    GridExtremes& g = pass == 0 ? lo_k : hi_k;
    for (std::size_t ia = 0; ia < b.alpha.size(); ++ia) {
      for (std::size_t ib = 0; ib < b.beta.size(); ++ib) {
        const double a = b.alpha[ia], be = b.beta[ib];
        const double da1 = d1 * std::tan(be) * std::sin(a), da2 = d2 * std::tan(be),
                     da3 = d3 / std::cos(be);
        const double da = std::sqrt(da1 * da1 + da2 * da2 + da3 * da3);
        const double db = std::abs(d1 * std::cos(a));
        const double gc = std::sqrt(da * da * std::cos(be) * std::cos(be) + db * db);
        const double w = a * a + be * be;
        const bool defined = w > 0;
        const double eq8 = defined ? std::sqrt((a * a * da * da + be * be * db * db) / w) : NAN;
        if (defined) {
          g.eq8_min = std::min(g.eq8_min, eq8);
          g.eq8_max = std::max(g.eq8_max, eq8);
        }
        g.gc_min = std::min(g.gc_min, gc);
        g.gc_max = std::max(g.gc_max, gc);
        if (pass == 1) {
          b.eq8_map_kmax[ia * b.beta.size() + ib] = eq8;
          b.great_circle_map_kmax[ia * b.beta.size() + ib] = gc;
        }
      }
    }
  }
  const double px = in.pixel_ifov * kArcsecPerRad;
  add("los_min", "LOS error, Eq. 8, least over the field, k' = k_min", "Eq. 8", lo_k.eq8_min,
      "arcsec");
  add("los_max", "LOS error, Eq. 8, greatest over the field, k' = k_max", "Eq. 8", hi_k.eq8_max,
      "arcsec");
  add("los_min_px", "LOS error in pixels, Eq. 8, least", "Sec. 3", lo_k.eq8_min / px, "px");
  add("los_max_px", "LOS error in pixels, Eq. 8, greatest", "Sec. 3", hi_k.eq8_max / px, "px");
  add("los_gc_min", "LOS error, great-circle combination, least over the field, k' = k_min",
      "corrected Eq. 8", lo_k.gc_min, "arcsec");
  add("los_gc_max", "LOS error, great-circle combination, greatest over the field, k' = k_max",
      "corrected Eq. 8", hi_k.gc_max, "arcsec");
  add("los_gc_max_px", "LOS error in pixels, great-circle, greatest", "corrected Eq. 8",
      hi_k.gc_max / px, "px");
  return b;
}

}  // namespace poise::models
