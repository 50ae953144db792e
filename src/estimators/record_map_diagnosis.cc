#include "estimators/record_map_diagnosis.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/angles.h"
#include "core/error.h"
#include "core/format.h"
#include "estimators/oscillation_detail.h"

namespace poise::estimators {
namespace {

using osc::Fit;
using osc::least_squares;

// The local noise level's half-width in cells: a motor's torque ripple holds many real orders
// close together (slots, poles and their sums), which a narrow neighbourhood would take for noise.
constexpr double kMapLocalCells = 40.0;

// The median angle step between moving rows (rad; 0 when none moves); span: the record's angle span.
double median_angle_step(const osc::Signals& s, double span) {
  std::vector<double> steps;
  for (Eigen::Index k = 1; k < s.phi.size(); ++k) {
    const double d = std::abs(s.phi[k] - s.phi[k - 1]);
    if (d > 1e-12 * std::max(1.0, span)) steps.push_back(d);
  }
  if (steps.empty()) return 0.0;
  std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2), steps.end());
  return steps[steps.size() / 2];
}

// The cogging orders a steps or laps record can show: from the lowest that completes a cycle
// over the span to half the rows per turn at the median angle step between moving rows.
osc::OrderRange map_orders(const RecordMotion& m, double median_step, const OscillationOptions& opt) {
  osc::OrderRange r;
  if (!(median_step > 0) || !(m.span > 0)) return r;
  r.max_order = static_cast<int>(std::min(2000.0, std::floor(angles::kPi / median_step)));
  if (opt.cogging_max_order > 0) r.max_order = std::min(r.max_order, opt.cogging_max_order);
  // The angle the rows stand for: the span and one step (a map of 512 points a turn apart by
  // 1/512 turn covers the whole turn).
  r.min_order = std::max(1, static_cast<int>(std::ceil(angles::kTwoPi / (m.span + median_step) - 1e-9)));
  r.limited_by_swing = r.min_order > 1;
  return r;
}

// The noise of each order from the record's two halves (in sample order), when each covers a
// turn: the pair's least-squares coefficients on each half of the residual (each half's mean
// removed), their difference Delta, and d = Delta^T (G_A^-1 + G_B^-1)^-1 Delta, which for noise
// alone is sigma^2 chi^2(2), as a drop is, while an order that is in both halves (a real, steady
// cogging order) cancels. Empty (count 0) when a half covers less than a turn.
osc::OrderScan split_half_noise(const Eigen::VectorXd& resid, const Eigen::VectorXd& phi, const osc::OrderRange& range,
                                double median_step) {
  osc::OrderScan noise;
  const Eigen::Index n = phi.size(), half = n / 2;
  auto covers_a_turn = [&](Eigen::Index a, Eigen::Index b) {
    const auto part = phi.segment(a, b - a);
    return part.maxCoeff() - part.minCoeff() + median_step >= angles::kTwoPi * (1.0 - 1e-9);
  };
  if (range.min_order > range.max_order || half < 16 || !covers_a_turn(0, half) || !covers_a_turn(half, n)) {
    return noise;
  }
  noise.first = range.min_order;
  noise.drop.assign(static_cast<std::size_t>(range.max_order - range.min_order + 1),
                    std::numeric_limits<double>::quiet_NaN());
  const Eigen::Index bounds[3] = {0, half, n};
  Eigen::VectorXd r(n);
  for (int h = 0; h < 2; ++h) {
    const auto part = resid.segment(bounds[h], bounds[h + 1] - bounds[h]);
    r.segment(bounds[h], bounds[h + 1] - bounds[h]) = (part.array() - part.mean()).matrix();
  }
  for (int order = range.min_order; order <= range.max_order; ++order) {
    Eigen::Vector2d coef[2];
    Eigen::Matrix2d inverse_sum = Eigen::Matrix2d::Zero();
    bool usable = true;
    for (int h = 0; h < 2 && usable; ++h) {
      Eigen::Matrix2d g = Eigen::Matrix2d::Zero();
      Eigen::Vector2d b = Eigen::Vector2d::Zero();
      for (Eigen::Index k = bounds[h]; k < bounds[h + 1]; ++k) {
        const Eigen::Vector2d x(std::sin(order * phi[k]), std::cos(order * phi[k]));
        g += x * x.transpose();
        b += x * r[k];
      }
      const Eigen::LDLT<Eigen::Matrix2d> ldlt(g);
      usable = ldlt.info() == Eigen::Success && g.determinant() > 1e-9 * g.trace() * g.trace();
      if (!usable) break;
      coef[h] = ldlt.solve(b);
      inverse_sum += ldlt.solve(Eigen::Matrix2d::Identity());
    }
    if (!usable) continue;
    const Eigen::Vector2d delta = coef[0] - coef[1];
    noise.drop[static_cast<std::size_t>(order - range.min_order)] = delta.dot(inverse_sum.ldlt().solve(delta));
    ++noise.count;
  }
  return noise;
}

OscillationParam param_of(const Fit& f, Eigen::Index i, const char* name) {
  return {name, f.beta[i], std::sqrt(std::max(0.0, f.cov(i, i))), "N*m"};
}

MapOrder order_from(const Fit& f, Eigen::Index k, int order, double resolution) {
  MapOrder o;
  o.order = order;
  o.resolution = resolution;
  const double a = f.beta[k], b = f.beta[k + 1];
  const double va = f.cov(k, k), vb = f.cov(k + 1, k + 1), vab = f.cov(k, k + 1);
  o.amplitude = std::hypot(a, b);
  o.phase = std::atan2(b, a);
  if (o.amplitude > 0) {
    o.se_amplitude = std::sqrt(std::max(0.0, a * a * va + 2 * a * b * vab + b * b * vb)) / o.amplitude;
    o.se_phase = std::sqrt(std::max(0.0, b * b * va - 2 * a * b * vab + a * a * vb)) / (o.amplitude * o.amplitude);
  }
  return o;
}

double bic_change(double rss_before, double rss_after, Eigen::Index n, Eigen::Index added) {
  return static_cast<double>(n) * std::log(rss_after / rss_before) +
         static_cast<double>(added) * std::log(static_cast<double>(n));
}

std::string turns_of(double turns) { return significant(turns, 3) + (turns > 1.0 ? " turns" : " turn"); }

void say_what_this_motion_cannot_show(const RecordMotion& m, const osc::OrderRange& range, bool trend_offered,
                                      MapDiagnosis& out) {
  const bool steps = m.kind == "steps";
  out.not_identifiable.emplace_back(
      "inertia", steps ? "a quasi-static map has no acceleration at its rows: a swing, or laps with speed steps, "
                         "would show it"
                       : "laps hold too little acceleration to show it: a swing, or laps with speed steps, "
                         "would show it");
  out.not_identifiable.emplace_back(
      "damping", steps ? "a quasi-static map has no velocity at its rows: laps at two or more speeds would show it"
                       : "one speed per direction cannot separate viscous damping from Coulomb friction: laps at "
                         "two or more speeds would show it");
  if (!(m.forward && m.backward)) {
    out.not_identifiable.emplace_back(
        "coulomb_friction",
        "the record moves in one direction only, so friction is part of M_0: a map or laps in both directions "
        "would separate it");
  }
  if (range.min_order > 1) {
    out.not_identifiable.emplace_back(
        "cogging", fmt::format("{} less than one cycle over the record's {}: a record of at least one turn "
                               "would show {}",
                               range.min_order == 2 ? std::string("order 1 completes")
                                                    : fmt::format("orders 1 to {} complete", range.min_order - 1),
                               turns_of(m.turns), range.min_order == 2 ? "it" : "them"));
  }
  if (!trend_offered && m.timed) {
    out.not_identifiable.emplace_back(
        "offset_drift",
        fmt::format("on {} in one direction the angle is nearly a function of time, so a slow drift "
                    "cannot be told from the lowest cogging orders: the lowest orders found may hold a drift, or "
                    "a drift an order; laps in both directions, or more turns, would separate them",
                    turns_of(m.turns)));
  }
}

// The estimates of the final model, in the order its columns were added (out.steps): every
// order's amplitude and phase jointly, the drift's slope, M_0 and the friction per direction.
void final_estimates(const Fit& cur, double resolution, MapDiagnosis& out) {
  const Eigen::Index first_order = out.coulomb_fitted ? 2 : 1;
  Eigen::Index column = first_order;
  std::size_t next_order = 0;
  for (const MapStep& step : out.steps) {
    if (step.effect == "offset_drift") {
      OscillationEffect& e = out.trends.front();
      e.params = {{"slope", cur.beta[column], std::sqrt(std::max(0.0, cur.cov(column, column))), "N*m/s"}};
      column += 1;
      continue;
    }
    MapOrder& o = out.orders[next_order++];
    const MapOrder joint = order_from(cur, column, o.order, resolution);
    o.amplitude = joint.amplitude, o.se_amplitude = joint.se_amplitude, o.phase = joint.phase;
    o.se_phase = joint.se_phase, o.resolution = joint.resolution;
    column += 2;
  }
  out.offset = param_of(cur, 0, "M_0");
  if (out.coulomb_fitted) {
    out.coulomb = param_of(cur, 1, "C");
    const double se = std::sqrt(std::max(0.0, cur.cov(0, 0) + cur.cov(1, 1) + 2 * cur.cov(0, 1)));
    const double se_back = std::sqrt(std::max(0.0, cur.cov(0, 0) + cur.cov(1, 1) - 2 * cur.cov(0, 1)));
    out.torque_forward = {"M_0 + C", cur.beta[0] + cur.beta[1], se, "N*m"};
    out.torque_backward = {"M_0 - C", cur.beta[0] - cur.beta[1], se_back, "N*m"};
    if (out.coulomb.value < -2.0 * out.coulomb.se) {
      out.outside_physics.push_back(fmt::format(
          "C = {} N*m < 0: the torque backward exceeds the torque forward, which friction cannot do; check the "
          "signs of the angle and of the current (or torque) columns",
          significant(out.coulomb.value, 3)));
    }
  }
}

}  // namespace

MapDiagnosis diagnose_map(const OscillationRecord& rec, const OscillationOptions& opt) {
  const osc::Signals s = osc::derive_signals(rec, opt);
  MapDiagnosis out;
  out.motion = osc::recognise_motion(s, !rec.no_time, opt.derivative_window);
  require(out.motion.kind != "swing", (rec.file.empty() ? std::string("record") : rec.file) +
                                          ": the record is a swing about a position; diagnose_oscillation reads it");
  out.n = s.n;
  out.median_step = s.dt, out.gaps = s.gaps, out.gap_total = s.gap_total, out.gap_largest = s.gap_largest;
  out.gap_largest_line = s.gap_largest_line;
  const auto n = static_cast<Eigen::Index>(s.n);
  out.rmse_constant = std::sqrt((s.y.array() - s.y.mean()).square().sum() / static_cast<double>(n));

  Eigen::MatrixXd model = Eigen::MatrixXd::Ones(n, 1);
  out.coulomb_fitted = out.motion.forward && out.motion.backward;
  if (out.coulomb_fitted) model = osc::joined(model, s.direction);
  const Eigen::MatrixXd base_model = model;
  const Fit base = least_squares(model, s.y);
  Fit cur = base;
  out.rmse_base = std::sqrt(cur.rss / static_cast<double>(n));

  const double median_step = median_angle_step(s, out.motion.span);
  const osc::OrderRange range = map_orders(out.motion, median_step, opt);
  const bool trend_offered = out.motion.timed && (out.coulomb_fitted || out.motion.turns > 2.0) && !rec.no_time;
  say_what_this_motion_cannot_show(out.motion, range, trend_offered, out);
  const double cell = std::max(1.0, angles::kTwoPi / std::max(out.motion.span, 1e-12));
  const double resolution = 0.5 * cell;
  const Eigen::VectorXd drift = (s.t.array() - s.t.mean()).matrix();
  bool drift_in = !trend_offered;
  for (int round = 0; round < kMaxOrders + 1 && static_cast<int>(out.orders.size()) < kMaxOrders; ++round) {
    // The best order of the round (Bonferroni over the orders scanned) and the trend (one test).
    const osc::OrderScan noise = split_half_noise(s.y - model * cur.beta, s.phi, range, median_step);
    const osc::ScanBest best =
        osc::scan_best(model, s.y, s.phi, range, cell, kMapLocalCells, noise.count > 0 ? &noise : nullptr);
    const int candidates = (best.test.order != 0 ? 1 : 0) + (drift_in ? 0 : 1);
    if (candidates == 0) break;
    double order_log_p = std::numeric_limits<double>::infinity(), order_dbic = 0.0;
    Fit order_fit;
    if (best.test.order != 0) {
      order_fit = least_squares(osc::joined(model, osc::cogging_columns(s.phi, best.test.order)), s.y);
      order_log_p = best.test.log_p + std::log(static_cast<double>(std::max(1, best.count)));
      order_dbic = bic_change(cur.rss, order_fit.rss, n, 2);
    }
    double drift_log_p = std::numeric_limits<double>::infinity(), drift_dbic = 0.0;
    Fit drift_fit;
    if (!drift_in && osc::independence(model, drift) > 1e-3) {
      drift_fit = least_squares(osc::joined(model, drift), s.y);
      drift_log_p = std::log(std::max(osc::f_test_p(cur.rss, drift_fit.rss, 1, n, model.cols() + 1), 1e-300));
      drift_dbic = bic_change(cur.rss, drift_fit.rss, n, 1);
    }
    const bool take_order = order_log_p <= drift_log_p;
    const double log_p = (take_order ? order_log_p : drift_log_p) + std::log(static_cast<double>(candidates));
    const double dbic = take_order ? order_dbic : drift_dbic;
    if (!(log_p < std::log(opt.alpha) && dbic < 0)) break;
    if (take_order) {
      model = osc::joined(model, osc::cogging_columns(s.phi, best.test.order));
      cur = order_fit;
      MapOrder o;
      o.order = best.test.order;
      o.p_value = std::exp(best.test.log_p), o.p_adjusted = std::min(1.0, std::exp(log_p)), o.delta_bic = dbic;
      out.orders.push_back(o);
      out.steps.push_back({fmt::format("order {}", o.order), std::sqrt(cur.rss / static_cast<double>(n))});
    } else {
      model = osc::joined(model, drift);
      cur = drift_fit;
      drift_in = true;
      OscillationEffect e;
      e.name = "offset_drift";
      e.p_value = std::exp(drift_log_p), e.p_adjusted = std::min(1.0, std::exp(log_p)), e.delta_bic = dbic;
      e.causes = "current-sensor offset drift (amplifier warm-up), motor heating changing K_T";
      out.trends.push_back(e);
      out.steps.push_back({"offset_drift", std::sqrt(cur.rss / static_cast<double>(n))});
    }
  }
  final_estimates(cur, resolution, out);
  out.rmse_after = std::sqrt(cur.rss / static_cast<double>(n));
  const Eigen::VectorXd after = s.y - model * cur.beta;
  const Eigen::VectorXd before = s.y - base_model * base.beta;
  out.angle.assign(s.phi.data(), s.phi.data() + n);
  out.residual_base.assign(before.data(), before.data() + n);
  out.residual_after.assign(after.data(), after.data() + n);
  return out;
}

}  // namespace poise::estimators
