#include <cmath>
#include <string>

#include <fmt/format.h>

#include "core/format.h"
#include "estimators/balancing_model_tests.h"
#include "estimators/complex_fit.h"

namespace poise::estimators {

using complex_fit::CMatrix;
using complex_fit::CVector;
using complex_fit::degrees_of;
using complex_fit::extra_sum_of_squares_p;
using complex_fit::Fit;
using complex_fit::fit;
using complex_fit::rms;

ModelTest test_runout(const std::vector<InfluenceCalibration>& speeds) {
  ModelTest t;
  t.name = "runout";
  const bool each_has_dof =
      std::all_of(speeds.begin(), speeds.end(), [](const InfluenceCalibration& c) { return c.dof > 0; });
  if (speeds.size() < 2) {
    t.needs =
        "readings at a second speed (runout stays, the unbalance response changes with speed), or an index "
        "run (the rotor turned on its mandrel)";
    return t;
  }
  const std::size_t sensors = speeds.front().sensors, planes = speeds.front().planes;
  const auto k = static_cast<Eigen::Index>(speeds.size()), s_count = static_cast<Eigen::Index>(sensors),
             p_count = static_cast<Eigen::Index>(planes);
  if (k * s_count <= p_count + s_count) {
    t.needs = "more sensors, or readings at a third speed";
    return t;
  }
  // Rows (speed, sensor): a_s(k) = sum_p h_sp(k) u_p [+ r_s], each weighted by 1/sd of a_s(k)
  // where the calibrations give it.
  CMatrix x0(k * s_count, p_count), x1(k * s_count, p_count + s_count);
  CVector y(k * s_count), weight_sd(k * s_count);
  x1.setZero();
  for (Eigen::Index i = 0; i < k; ++i) {
    const auto& c = speeds[static_cast<std::size_t>(i)];
    for (Eigen::Index s = 0; s < s_count; ++s) {
      const auto su = static_cast<std::size_t>(s);
      const double sd = each_has_dof ? std::sqrt(c.noise_var[su] * c.design_inverse[0].real()) : 1.0;
      const Eigen::Index row = i * s_count + s;
      weight_sd(row) = sd;
      y(row) = c.initial[su].value / sd;
      for (Eigen::Index p = 0; p < p_count; ++p) x0(row, p) = c.h[su][static_cast<std::size_t>(p)].value / sd;
      x1.block(row, 0, 1, p_count) = x0.row(row);
      x1(row, p_count + s) = 1.0 / sd;
    }
  }
  const Fit f0 = fit(x0, y), f1 = fit(x1, y);
  const Eigen::Index q = f1.rank - f0.rank, nu = y.size() - f1.rank;
  if (q <= 0 || nu <= 0 || !(f1.rss > 0.0)) {
    t.needs = "more sensors or speeds: runout and unbalance are not separable on these readings";
    return t;
  }
  t.ran = true;
  t.p_value = extra_sum_of_squares_p(f0, f1, q, nu);
  t.significant = *t.p_value < kModelTestLevel;
  // Residuals in the amplitude unit (the fits are weighted).
  t.residual_before = rms((y - x0 * f0.beta).cwiseProduct(weight_sd).squaredNorm(), y.size());
  t.residual_after = rms((y - x1 * f1.beta).cwiseProduct(weight_sd).squaredNorm(), y.size());
  std::string runout, unbalance;
  for (Eigen::Index s = 0; s < s_count; ++s) {
    const Phasor r = f1.beta(p_count + s);
    runout += fmt::format("{}{} @ {:.0f} deg", s ? ", " : "", significant(std::abs(r), 3), degrees_of(r));
  }
  std::string correction;
  for (Eigen::Index p = 0; p < p_count; ++p) {
    const Phasor u = f1.beta(p);
    unbalance += fmt::format("{}{} g @ {:.1f} deg", p ? ", " : "", significant(std::abs(u), 4), degrees_of(u));
    correction += fmt::format("{}{} g @ {:.1f} deg", p ? ", " : "", significant(std::abs(u), 4), degrees_of(-u));
  }
  t.finding = "a reading that does not follow the masses (runout per sensor, the amplitude unit, lag: " + runout +
              "); the rotor's own unbalance without it: " + unbalance +
              ", and the correction that cancels it: " + correction +
              " (angles as Poise counts them: against rotation; the runout's readings stay)";
  return t;
}

}  // namespace poise::estimators
