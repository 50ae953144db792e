#include "estimators/oscillation_diagnosis.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <string>

#include "core/angles.h"
#include "core/format.h"
#include "estimators/oscillation_detail.h"

namespace poise::estimators {
namespace {

using osc::Fit;
using osc::least_squares;
using osc::Signals;

struct Candidate {
  std::string name;
  int order = 0;
  double resolution = 0.0;  ///< cogging: the order's (CoggingPick)
  Eigen::MatrixXd cols;
  std::string causes;
};

struct Tested {
  Candidate cand;
  double p, p_family, dbic;
  Fit fit;
  /// Ranks the round's candidates: ln of the family's p (uncapped, in logs: p underflows), for
  /// cogging that of its F were the noise level known (chi^2(2) / 2: a level estimated from a
  /// few neighbouring orders caps p, not the effect's strength).
  double log_p_rank;
};

OscillationParam param(const Fit& f, Eigen::Index i, const char* name, const char* unit) {
  return OscillationParam{name, f.beta[i], std::sqrt(f.cov(i, i)), unit};
}

// The base model: constant, B, C, the spring K (gravity's pendulum stiffness plus any cable,
// about the mean angle: phi from the encoder, noise-free to its resolution), J where the
// motion separates phi'' from phi (a purely sinusoidal motion has phi'' = -omega^2 (phi -
// mean): the twice-differenced encoder then adds only its quantisation noise, times J, so the
// phi column carries both and is reported as J = -K / omega^2, omega^2 from the regression of
// phi'' on phi - mean, as a spring lumped into J), and the curvature of gravity's torque over the swing
// (cos(phi - mean) - 1, centred: a pendulum torque U sin(a + delta) = U sin a cos delta +
// U cos a sin delta, whose cos part is quadratic in the angle and matters at swings of
// several degrees; kept where it can reach a 3-sigma matched filter). A column with less than
// 5 % of its norm independent of the others is left out.
Eigen::MatrixXd base_model(const Signals& s, OscillationDiagnosis& out, bool& inertia, bool& curvature) {
  const auto ne = static_cast<Eigen::Index>(s.n);
  Eigen::MatrixXd model(ne, 4);
  model.col(0) = Eigen::VectorXd::Ones(ne);
  model.col(1) = s.rate;
  model.col(2) = s.direction;
  model.col(3) = (s.phi.array() - s.phi.mean()).matrix();
  inertia = osc::independence(model, s.acc) >= 0.05;
  if (inertia) {
    model = osc::joined(model, s.acc);
  } else {
    out.not_identifiable.emplace_back(
        "spring",
        "the motion is too purely sinusoidal to separate a spring (gravity's pendulum stiffness, "
        "cable) from the inertia; it is lumped into J");
  }
  Eigen::VectorXd bend = ((s.phi.array() - s.phi.mean()).cos() - 1.0).matrix();
  bend.array() -= bend.mean();
  curvature = bend.norm() > 0.0 && osc::independence(model, bend) >= 0.05;
  if (curvature) {
    // Kept only where the swing can show it: its coefficient, gravity's torque at the mean
    // angle, is at most |M_0| (the position's torque), so its matched filter over the record
    // reaches at most |M_0| |bend| / sigma; below 3 it is left out (at a swing of a few
    // degrees a quadratic in the angle would only trade off with cogging of few cycles).
    const Fit f = least_squares(model, s.y);
    const double sigma = std::sqrt(f.rss / static_cast<double>(std::max<Eigen::Index>(1, ne - model.cols())));
    curvature = std::abs(f.beta[0]) * bend.norm() >= 3.0 * sigma;
    if (curvature) model = osc::joined(model, bend);
  }
  return model;
}

Tested test_columns(const Eigen::MatrixXd& model, const Eigen::VectorXd& y, const Fit& cur, Candidate c,
                    double family) {
  const Eigen::MatrixXd x = osc::joined(model, c.cols);
  const Fit f = least_squares(x, y);
  const auto n = static_cast<long>(y.size());
  const double p = osc::f_test_p(cur.rss, f.rss, c.cols.cols(), n, x.cols());
  const double dbic = static_cast<double>(n) * std::log(f.rss / cur.rss) +
                      static_cast<double>(c.cols.cols()) * std::log(static_cast<double>(n));
  return {std::move(c), p, std::min(1.0, p * family), dbic, f, std::log(p * family)};
}

// The round's cogging candidate (osc::pick_cogging): the orders scanned over the whole record
// and on the samples away from the reversals (the model refitted there), each judged against
// the larger of the residual's white and local noise levels; the smaller p of the two scans,
// Bonferroni over all the orders they examined; the delta BIC is that of the samples of the
// scan that found it. Ranked among the round's candidates by the p its F would have were the
// noise level known (log_p_rank). The order is refused when it sits at the swing's limit or
// fits more than the residual can hold (each said in out.not_identifiable, and the family
// closed).
std::optional<Tested> cogging_candidate(const Signals& s, const Eigen::MatrixXd& model, const Fit& cur,
                                        const osc::OrderRange& range, double plausible, OscillationDiagnosis& out,
                                        bool& closed) {
  const osc::Moving mv = osc::away_from_reversals(s, model);
  const osc::CoggingPick pick = osc::pick_cogging(s, model, mv, range);
  const osc::LocalTest& lt = pick.test;
  if (pick.count == 0 || lt.order == 0) return std::nullopt;
  Tested t = test_columns(model, s.y, cur,
                          {"cogging", lt.order, pick.resolution, osc::cogging_columns(s.phi, lt.order),
                           "motor cogging (slot/pole detent) or a periodic drag of the bearing cage"},
                          1.0);
  if (pick.on_moving) {
    const Fit mfit = least_squares(mv.model, mv.y);
    t.dbic =
        test_columns(mv.model, mv.y, mfit, {"cogging", lt.order, 0.0, osc::cogging_columns(mv.phi, lt.order), ""}, 1.0)
            .dbic;
  }
  const double log_count = std::log(static_cast<double>(pick.count));
  t.log_p_rank = -lt.f + log_count;
  t.p = std::exp(lt.log_p), t.p_family = std::min(1.0, std::exp(lt.log_p + log_count));
  const Eigen::Index k0 = model.cols();
  const double amp = std::hypot(t.fit.beta[k0], t.fit.beta[k0 + 1]);
  std::string why;
  if (pick.at_edge) {
    why = fmt::format(
        "the best order, {}, lies at the swing's limit (orders from {} are scanned): the "
        "structure most likely belongs to a lower order that this swing cannot identify; "
        "not added. A larger swing would test the lower orders",
        lt.order, range.min_order);
  } else if (amp > plausible) {
    why = fmt::format(
        "the best order, {}, fits an amplitude of {:.3g} N*m, more than the {:.3g} N*m the base "
        "residual can hold (2 sqrt(2) x its RMS): it trades off with the base terms and is "
        "refused as implausible",
        lt.order, amp, plausible);
  } else {
    return t;
  }
  out.not_identifiable.emplace_back("cogging", std::move(why));
  closed = true;
  return std::nullopt;
}

OscillationEffect to_effect(const Tested& top, double p_adj, Eigen::Index k0) {
  OscillationEffect eff;
  eff.name = top.cand.name;
  eff.order = top.cand.order;
  eff.order_resolution = top.cand.resolution;
  eff.p_value = top.p;
  eff.p_adjusted = p_adj;
  eff.delta_bic = top.dbic;
  eff.causes = top.cand.causes;
  const Fit& f = top.fit;
  if (eff.name == "cogging") {
    // Motor torque a sin(N phi) + b cos(N phi) = T sin(N phi + psi) balances a cogging
    // torque -T sin(N phi + psi).
    const double a = f.beta[k0], b = f.beta[k0 + 1];
    const double amp = std::hypot(a, b);
    const double va = f.cov(k0, k0), vb = f.cov(k0 + 1, k0 + 1), vab = f.cov(k0, k0 + 1);
    const double se_amp = amp > 0 ? std::sqrt((a * a * va + 2 * a * b * vab + b * b * vb)) / amp : 0.0;
    const double se_ph = amp > 0 ? std::sqrt(b * b * va - 2 * a * b * vab + a * a * vb) / (amp * amp) : 0.0;
    eff.params = {{"amplitude", amp, se_amp, "N*m"}, {"phase", std::atan2(b, a), se_ph, "rad"}};
  } else {
    const bool drift = eff.name == "offset_drift";
    eff.params = {{drift ? "slope" : "asymmetry", f.beta[k0], std::sqrt(f.cov(k0, k0)), drift ? "N*m/s" : "N*m"}};
  }
  return eff;
}

}  // namespace

OscillationDiagnosis diagnose_oscillation(const OscillationRecord& rec, const OscillationOptions& opt) {
  const Signals s = osc::derive_signals(rec, opt);
  OscillationDiagnosis out;
  out.n = s.n;
  out.torque_eq21 = rec.torque.empty() ? opt.kt * std::accumulate(rec.current.begin(), rec.current.end(), 0.0) /
                                             static_cast<double>(rec.current.size())
                                       : std::accumulate(rec.torque.begin(), rec.torque.end(), 0.0) /
                                             static_cast<double>(rec.torque.size());
  out.gaps = s.gaps, out.gap_total = s.gap_total, out.gap_largest = s.gap_largest;
  out.gap_largest_line = s.gap_largest_line;
  out.median_step = s.dt;
  bool inertia = false, curvature = false;
  Eigen::MatrixXd model = base_model(s, out, inertia, curvature);
  const Eigen::MatrixXd base_columns = model;
  const Fit base = least_squares(model, s.y);
  out.torque_before = param(base, 0, "M_0", "N*m");
  if (inertia) {
    out.base_before = {param(base, 4, "J", "kg*m^2"), param(base, 1, "B", "N*m*s/rad"), param(base, 2, "C", "N*m"),
                       param(base, 3, "K", "N*m/rad")};
  } else {
    // J + K / (-omega^2) in one: the phi column's coefficient over -omega^2.
    const Eigen::VectorXd delta = (s.phi.array() - s.phi.mean()).matrix();
    const double w2 = -s.acc.dot(delta) / delta.squaredNorm();
    OscillationParam j = param(base, 3, "J", "kg*m^2");
    j.value /= -w2, j.se /= std::abs(w2);
    out.base_before = {j, param(base, 1, "B", "N*m*s/rad"), param(base, 2, "C", "N*m")};
  }
  if (curvature) out.base_before.push_back(param(base, model.cols() - 1, "G", "N*m"));
  out.rmse_before = std::sqrt(base.rss / static_cast<double>(s.n));

  std::vector<Candidate> fixed;
  fixed.push_back({"offset_drift", 0, 0.0, (s.t.array() - s.t.mean()).matrix(),
                   "current-sensor offset drift (amplifier warm-up), motor heating changing K_T"});
  fixed.push_back({"coulomb_asymmetry", 0, 0.0, s.direction.unaryExpr([](double v) { return v > 0 ? 1.0 : 0.0; }),
                   "direction-dependent bearing friction (preload, lubricant, seal)"});
  const osc::OrderRange range = osc::cogging_orders(s, opt, out);
  const double plausible = 2.0 * std::sqrt(2.0) * out.rmse_before;  // largest amplitude the residual holds
  bool cogging_in = range.min_order > range.max_order;
  std::vector<std::string> added;
  Fit cur = base;
  for (int round = 0; round < 8; ++round) {
    std::vector<Tested> tested;
    for (const auto& c : fixed) {
      if (std::find(added.begin(), added.end(), c.name) != added.end()) continue;
      if (osc::independence(model, c.cols) < 1e-3) {
        if (round == 0) {
          out.not_identifiable.emplace_back(
              c.name,
              "a constant friction asymmetry is, at one position, the unbalance torque's alias: it "
              "biases M_0 (and Eq. 21) by half the asymmetry; separate it with tests at two "
              "oscillation centres or by comparing turntable directions");
        }
        continue;
      }
      tested.push_back(test_columns(model, s.y, cur, c, 1.0));
    }
    if (!cogging_in) {
      auto c = cogging_candidate(s, model, cur, range, plausible, out, cogging_in);
      if (c) tested.push_back(std::move(*c));
    }
    if (tested.empty()) break;
    // Holm across the round's candidates (each family counted once): the smallest first.
    const auto top_it = std::min_element(tested.begin(), tested.end(),
                                         [](const Tested& a, const Tested& b) { return a.log_p_rank < b.log_p_rank; });
    const Tested& top = *top_it;
    const double p_adj = std::min(1.0, top.p_family * static_cast<double>(tested.size()));
    out.rounds = round + 1;
    if (!(p_adj < opt.alpha && top.dbic < 0)) break;
    out.effects.push_back(to_effect(top, p_adj, model.cols()));
    if (top.cand.name == "cogging") {
      cogging_in = true;
    } else {
      added.push_back(top.cand.name);
    }
    model = osc::joined(model, top.cand.cols);
    cur = top.fit;
  }
  out.torque_after = param(cur, 0, "M_0", "N*m");
  out.rmse_after = std::sqrt(cur.rss / static_cast<double>(s.n));
  const Eigen::VectorXd after = s.y - model * cur.beta, before = s.y - base_columns * base.beta;
  out.angle.assign(s.phi.data(), s.phi.data() + s.phi.size());
  out.residual_base.assign(before.data(), before.data() + before.size());
  out.residual_after.assign(after.data(), after.data() + after.size());
  return out;
}

}  // namespace poise::estimators
