#include "budget/slip_detection.h"

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/format.h"
#include "core/units.h"

namespace poise::budget {
namespace {

using sampling::DistributionKind;
using sampling::ToleranceConvention;

Range scaled(const Range& r, double f) { return {r.least * f, r.greatest * f}; }

std::string sigmas_text(ToleranceConvention c) {
  switch (c) {
    case ToleranceConvention::kOneSigma: return "1 sigma";
    case ToleranceConvention::kTwoSigma: return "2 sigma";
    case ToleranceConvention::kThreeSigma: return "3 sigma";
    case ToleranceConvention::kBounds: return "bounds";
  }
  return "?";
}

// Ratio declared / recomputed when it is one number over the compared ends (nullopt when the
// ends call for different factors or a recomputed end is zero).
std::optional<double> common_ratio(const Declared& d, const Range& r) {
  if (!(r.greatest > 0)) return std::nullopt;
  const double hi = d.greatest / r.greatest;
  if (!d.ranged) return hi;
  if (!(r.least > 0)) return std::nullopt;
  const double lo = d.least / r.least;
  if (std::abs(lo - hi) > 0.01 * std::abs(hi)) return std::nullopt;
  return 0.5 * (lo + hi);
}

// A unit or level factor that explains the ratio, or "".
std::string factor_slip(const Declared& d, const Range& r, int level) {
  for (int k = 1; k <= 3; ++k) {
    if (k == level) continue;
    const double f = static_cast<double>(k) / level;
    if (agrees(d, scaled(r, f))) {
      return "level mix-up: the declared value is " + ratio_text(f) + " x the recomputed one, a " + std::to_string(k) +
             "-sigma figure in a " + std::to_string(level) + "-sigma budget";
    }
  }
  struct Factor {
    double f;
    const char* what;
  };
  const double deg = 180.0 / std::numbers::pi;
  const Factor factors[] = {
      {deg, "degrees/radians: the declared value is 57.3 x the recomputed one (radians read as degrees)"},
      {1 / deg, "degrees/radians: the declared value is 1/57.3 x the recomputed one (degrees read as radians)"},
      {60, "a unit slip: the declared value is 60 x the recomputed one (arcmin/arcsec or deg/arcmin)"},
      {1.0 / 60, "a unit slip: the declared value is 1/60 x the recomputed one (arcsec/arcmin or arcmin/deg)"},
      {3600, "a unit slip: the declared value is 3600 x the recomputed one (deg/arcsec)"},
      {1.0 / 3600, "a unit slip: the declared value is 1/3600 x the recomputed one (arcsec/deg)"},
      {1000, "a unit slip: the declared value is 1000 x the recomputed one (mm/um, mrad/urad)"},
      {1e-3, "a unit slip: the declared value is 1/1000 x the recomputed one (um/mm, urad/mrad)"},
      {units::kArcsecPerRad, "a unit slip: the declared value is 206265 x the recomputed one (radians/arcsec)"},
  };
  for (const auto& f : factors) {
    if (agrees(d, scaled(r, f.f))) return f.what;
  }
  return "";
}

std::string convention_slip(const BudgetEvaluator& ev, const LineSpec& l, const Declared& d, const Range& r) {
  const DistributionKind kinds[] = {DistributionKind::kNormal, DistributionKind::kUniform, DistributionKind::kArcsine,
                                    DistributionKind::kTruncatedNormal};
  const ToleranceConvention conventions[] = {ToleranceConvention::kBounds, ToleranceConvention::kOneSigma,
                                             ToleranceConvention::kTwoSigma, ToleranceConvention::kThreeSigma};
  // Same distribution first, then the others.
  for (int pass = 0; pass < 2; ++pass) {
    for (DistributionKind k : kinds) {
      if ((pass == 0) != (k == l.distribution)) continue;
      for (ToleranceConvention c : conventions) {
        if (k == l.distribution && c == l.convention) continue;
        LineSpec v = l;
        v.distribution = k;
        v.convention = c;
        Range alt;
        try {
          alt = ev.line_range_as(v);
        } catch (const Error&) {
          continue;  // a combination the conventions refuse (normal with bounds, ...)
        }
        if (!agrees(d, alt)) continue;
        const std::string ratio = ratio_text(alt.greatest / r.greatest);
        if (k == l.distribution && l.convention == ToleranceConvention::kBounds &&
            c == ToleranceConvention::kOneSigma) {
          return "bounds read as sigma: the declared value is " + ratio + " x the recomputed one (the " +
                 sampling::to_string(k) + " law's +-t taken as its standard deviation)";
        }
        if (k == l.distribution) {
          return "a " + sigmas_text(l.convention) + " tolerance read as " + sigmas_text(c) +
                 ": the declared value is " + ratio + " x the recomputed one";
        }
        return "the tolerance read as " + sampling::to_string(k) + " " + sigmas_text(c) + " instead of " +
               sampling::to_string(l.distribution) + " " + sigmas_text(l.convention) + ": the declared value is " +
               ratio + " x the recomputed one";
      }
    }
  }
  return "";
}

std::string gain_slip(const BudgetEvaluator& ev, const LineSpec& l, const Declared& d) {
  const std::string& g = l.gain;
  if (g == "1") return "";
  const std::string the_gain = "the gain (" + g + ")";
  LineSpec v = l;
  v.gain.assign(1, '1');  // not = "1": GCC 12's -Wrestrict false positive (PR 105329) on that assignment
  if (agrees(d, ev.line_range_as(v))) return the_gain + " left out";
  v.gain = "1/(" + g + ")";
  try {
    if (agrees(d, ev.line_range_as(v))) return the_gain + " inverted: divided by where it multiplies";
  } catch (const Error&) {
  }
  const auto& field = ev.spec().field;
  std::vector<double> scale(field.size(), 1.0);
  bool any_angle = false;
  for (std::size_t k = 0; k < field.size(); ++k) {
    if (field[k].angle) {
      scale[k] = 180.0 / std::numbers::pi;
      any_angle = true;
    }
  }
  if (any_angle && agrees(d, ev.line_range_as(l, &scale))) {
    return the_gain + " evaluated with the angles in degrees as if they were radians";
  }
  return "";
}

std::string unit_of(const std::string& text) {
  const auto space = text.find_first_of(" \t");
  if (space == std::string::npos) return "";
  std::string u = text.substr(space + 1);
  while (!u.empty() && u.front() == ' ') u.erase(0, 1);
  return u;
}

std::string formatted(double si, const std::string& as_written) {
  const std::string u = unit_of(as_written);
  try {
    return u.empty() ? std::to_string(si) : units::format(si, u, 3);
  } catch (const Error&) {
    return std::to_string(si);
  }
}

std::string lever_slip(const BudgetEvaluator& ev, const LineSpec& l, const Declared& d, const Range& r) {
  if (!l.lever) return "";
  for (const auto& other : ev.spec().lines) {
    if (!other.lever || std::abs(*other.lever - *l.lever) <= 1e-9 * *l.lever) continue;
    LineSpec v = l;
    v.lever = other.lever;
    if (agrees(d, ev.line_range_as(v))) {
      return "the lever of line \"" + other.name + "\" (" + other.lever_text + ") used instead of " + l.lever_text;
    }
  }
  (void)r;
  return "";
}

std::string fallback_slip(const LineSpec& l, const Declared& d, const Range& r) {
  const auto ratio = common_ratio(d, r);
  if (!ratio || *ratio <= 0) return "";
  std::string out = "the declared value is " + ratio_text(*ratio) + " x the recomputed one: it would follow from ";
  if (l.lever) {
    out += "a lever " + ratio_text(1.0 / *ratio) + " x the stated one (" + formatted(*l.lever / *ratio, l.lever_text) +
           " instead of " + l.lever_text + "), or ";
  }
  out += "a tolerance of " + formatted(l.tolerance * *ratio, l.tolerance_text) + " instead of " + l.tolerance_text;
  return out;
}

}  // namespace

std::string ratio_text(double r) {
  struct Named {
    double v;
    const char* text;
  };
  const Named named[] = {{std::sqrt(3.0), "sqrt(3)"},
                         {std::sqrt(2.0), "sqrt(2)"},
                         {1 / std::sqrt(3.0), "1/sqrt(3)"},
                         {1 / std::sqrt(2.0), "1/sqrt(2)"},
                         {2.0, "2"},
                         {3.0, "3"},
                         {0.5, "1/2"},
                         {1.0 / 3, "1/3"},
                         {1.5, "1.5"},
                         {2.0 / 3, "2/3"},
                         {std::sqrt(6.0), "sqrt(6)"},
                         {1 / std::sqrt(6.0), "1/sqrt(6)"}};
  for (const auto& n : named) {
    if (std::abs(r - n.v) <= 0.005 * n.v) return n.text;
  }
  return significant(r, 3);
}

std::string line_slip(const BudgetEvaluator& ev, std::size_t item, const Declared& d, const Range& r) {
  const LineSpec& l = ev.spec().lines[item];
  if (l.given || !d.present) return "";
  if (l.distribution != DistributionKind::kFixed) {
    if (auto s = convention_slip(ev, l, d, r); !s.empty()) return s;
  }
  if (auto s = factor_slip(d, r, ev.spec().level); !s.empty()) return s;
  if (auto s = gain_slip(ev, l, d); !s.empty()) return s;
  if (auto s = lever_slip(ev, l, d, r); !s.empty()) return s;
  return fallback_slip(l, d, r);
}

std::string node_slip(const BudgetEvaluator& ev, std::optional<std::size_t> item, const Declared& d, const Range& r,
                      const std::vector<const ItemResult*>& results) {
  if (!d.present) return "";
  const std::vector<std::size_t>& entries = item ? ev.members(*item) : ev.top();
  auto range = [&](const Mode& m) { return item ? ev.item_range(*item, m) : ev.combined_range(m); };
  // 1. The declared members, combined, give the declared figure: the slip is upstream.
  bool any_declared = false;
  for (std::size_t k : entries) any_declared = any_declared || ev.declared(k).present;
  if (any_declared) {
    Mode lo, hi;
    lo.declared = Mode::Declared::kLeast;
    hi.declared = Mode::Declared::kGreatest;
    const Range from{range(lo).least, range(hi).greatest};
    if (agrees(d, from)) {
      std::string upstream;
      for (std::size_t k : entries) {
        if (results[k] && results[k]->verdict.verdict == "disagrees") {
          upstream += (upstream.empty() ? "\"" : ", \"") + ev.name(k) + "\"";
        }
      }
      return "it follows from the declared values of its entries" +
             (upstream.empty() ? std::string(" (rounded)") : ": the difference comes from " + upstream);
    }
  }
  // 2. Another rule.
  const Combination own = item ? ev.spec().groups[*item - ev.spec().lines.size()].combination : ev.spec().combination;
  for (Combination c : {Combination::kRss, Combination::kLinear, Combination::kBiasLinearRandomRss}) {
    if (c == own) continue;
    Mode m;
    m.rule = c;
    if (agrees(d, range(m))) return "combined by " + to_string(c) + " instead of " + to_string(own);
  }
  // 3. An entry left out.
  if (entries.size() > 1) {
    for (std::size_t k : entries) {
      Mode m;
      m.left_out = k;
      if (agrees(d, range(m))) return "\"" + ev.name(k) + "\" left out";
    }
  }
  // 4. The propagation factors left out.
  Mode no_propagation;
  no_propagation.use_propagation = false;
  if (agrees(d, range(no_propagation))) return "the propagation factors left out";
  // 5. A level or unit factor.
  if (auto s = factor_slip(d, r, ev.spec().level); !s.empty()) return s;
  if (const auto ratio = common_ratio(d, r)) {
    return "the declared value is " + ratio_text(*ratio) + " x the recomputed one (no single slip found)";
  }
  return "";
}

}  // namespace poise::budget
