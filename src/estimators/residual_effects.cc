#include "estimators/residual_effects.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/angles.h"

namespace poise::estimators::detail {
namespace {

using angles::kPi;
using angles::wrap_two_pi;
using Eigen::Index;
constexpr double kDegPerRad = 180.0 / kPi;

constexpr const char* kCauseHarmonic2 =
    "Anisotropic elastic sag of the rotor or frame under gravity (quadratic in gravity), an "
    "out-of-round bearing or race under the gravity load, or a current or torque sensor "
    "nonlinear (quadratic) in torque. Not an axis tilt: that changes the first harmonic only.";
constexpr const char* kCauseHarmonicHigh =
    "Race waviness, cogging of the turntable drive, or a mass distribution with higher moments "
    "coupled through compliance.";
constexpr const char* kCauseDrift =
    "Motor or amplifier heating, current-sensor offset drift, or K_T changing with temperature.";
constexpr const char* kCauseDirection = "Backlash in the turntable, cable wind-up, or hysteresis of the flex leads.";
constexpr const char* kCauseOutlier =
    "A disturbed point: turntable not settled or not locked, a bump, or a missed period.";
constexpr const char* kCauseAr =
    "A slow disturbance spanning several positions: thermal drift, or settling not complete.";
constexpr const char* kCauseStep =
    "A level shift: the amplifier or current sensor re-zeroed, a knock that moved a lead or a "
    "cable, a range switch of the acquisition.";
constexpr const char* kCauseExponential =
    "Thermal settling after switch-on: motor winding, amplifier or bearing grease warming to "
    "equilibrium (a first-order lag).";
constexpr const char* kCauseKt =
    "The torque constant changing during the test (magnet and winding temperature: NdFeB about "
    "-0.1 %/K), scaling the whole measured torque.";

struct Polar {
  double amplitude, phase, se_amplitude, se_phase;
};

// (a, c) of a sin + c cos -> amplitude, phase with delta-method SE (as in fit_sine).
Polar polar(double a, double c, const Eigen::Matrix2d& cov) {
  Polar p{std::hypot(a, c), wrap_two_pi(std::atan2(c, a)), 0.0, 0.0};
  if (p.amplitude > 0.0) {
    const Eigen::Vector2d ua(a / p.amplitude, c / p.amplitude), up(-ua(1), ua(0));
    p.se_amplitude = std::sqrt(std::max(0.0, ua.dot(cov * ua)));
    p.se_phase = std::sqrt(std::max(0.0, up.dot(cov * up))) / p.amplitude;
  } else {
    p.se_amplitude = std::sqrt(0.5 * (cov(0, 0) + cov(1, 1)));
    p.se_phase = std::numeric_limits<double>::infinity();
  }
  return p;
}

}  // namespace

const char* causes_of(const std::string& name, int order) {
  if (name == "harmonic") return order == 2 ? kCauseHarmonic2 : kCauseHarmonicHigh;
  if (name == "time_drift" || name == "time_drift_quadratic") return kCauseDrift;
  if (name == "step") return kCauseStep;
  if (name == "exponential_drift") return kCauseExponential;
  if (name == "kt_drift") return kCauseKt;
  if (name == "direction_offset") return kCauseDirection;
  if (name == "outlier") return kCauseOutlier;
  return kCauseAr;
}

Effect to_effect(const Term& t, const Model& m, const LinearFit& f, const TorqueTable& table) {
  Effect e;
  e.name = t.name, e.order = t.order, e.index = t.index;
  e.p_value = t.p, e.p_adjusted = t.p_adj, e.delta_bic = t.delta_bic;
  e.causes = causes_of(t.name, t.order);
  const std::string& u = table.unit;
  const std::string per = table.time_s.empty() ? "/measurement" : "/s";
  const auto coef = [&](Index k) {
    return EffectParam{"", f.beta(t.first + k), std::sqrt(f.cov(t.first + k, t.first + k)), u};
  };
  if (t.name == "harmonic") {
    const Polar p = polar(f.beta(t.first), f.beta(t.first + 1), f.cov.block<2, 2>(t.first, t.first));
    e.params = {{"amplitude", p.amplitude, p.se_amplitude, u},
                {"phase_deg", p.phase * kDegPerRad, p.se_phase * kDegPerRad, "deg"}};
  } else if (t.name == "time_drift" || t.name == "time_drift_quadratic") {
    const bool quad = t.name == "time_drift_quadratic";
    EffectParam p = coef(0);
    p.name = quad ? "curvature" : "slope";
    p.unit = u + per + (quad ? "^2" : "");
    e.params = {p};
  } else if (t.name == "step") {
    EffectParam p = coef(0);
    p.name = "level_change";
    const auto row = static_cast<std::size_t>(t.index);
    const double at = table.time_s.empty() ? static_cast<double>(row) : table.time_s[row];
    e.params = {p,
                {"first_row_after", static_cast<double>(row), 0.0, ""},
                {"at_time", at, std::numeric_limits<double>::quiet_NaN(), table.time_s.empty() ? "measurement" : "s"}};
    e.line = row < table.rows.size() ? table.rows[row] : 0;
  } else if (t.name == "exponential_drift") {
    EffectParam p = coef(0);
    p.name = "initial_excess";
    e.params = {p,
                {"tau", t.param, std::numeric_limits<double>::quiet_NaN(), table.time_s.empty() ? "measurement" : "s"}};
  } else if (t.name == "kt_drift") {
    EffectParam p = coef(0);
    p.name = "relative_rate";
    p.unit = per.substr(1) == "s" ? "1/s" : "1/measurement";
    e.params = {p};
  } else if (t.name == "direction_offset") {
    EffectParam p = coef(0);
    p.name = "half_difference";
    e.params = {p};
  } else if (t.name == "outlier") {
    EffectParam p = coef(0);
    p.name = "offset";
    e.params = {p};
    const auto row = static_cast<std::size_t>(t.index);
    e.line = row < table.rows.size() ? table.rows[row] : 0;
  } else {
    e.params = {{"rho", m.rho.rho, m.rho.se, ""}};
  }
  return e;
}

}  // namespace poise::estimators::detail
