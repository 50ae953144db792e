#include "estimators/oscillation_diagnosis.h"

#include <Eigen/Dense>
#include <boost/math/distributions/fisher_f.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>

#include "core/angles.h"
#include "core/error.h"

namespace poise::estimators {
namespace {

// A number in a message: 6 significant digits ("1e+308", never 309 digits).
std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

struct Fit {
  Eigen::VectorXd beta;
  Eigen::MatrixXd cov;
  double rss = 0.0;
};

Fit least_squares(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(x);
  Fit f;
  f.beta = qr.solve(y);
  const Eigen::VectorXd r = y - x * f.beta;
  f.rss = r.squaredNorm();
  const double dof = static_cast<double>(x.rows() - x.cols());
  const Eigen::MatrixXd xtx_inv = (x.transpose() * x).inverse();
  f.cov = xtx_inv * (f.rss / std::max(1.0, dof));
  return f;
}

double f_test_p(double rss0, double rss1, long q, long n, long p1) {
  if (!std::isfinite(rss0) || !std::isfinite(rss1) || rss1 <= 0 || rss0 <= rss1 || n - p1 < 1) return 1.0;
  const double f = ((rss0 - rss1) / static_cast<double>(q)) / (rss1 / static_cast<double>(n - p1));
  boost::math::fisher_f dist(static_cast<double>(q), static_cast<double>(n - p1));
  return boost::math::cdf(boost::math::complement(dist, f));
}

// Fraction of the candidate columns' norm left after projecting out the model's columns:
// ~0 means the candidate is (numerically) in the model's span.
double independence(const Eigen::MatrixXd& model, const Eigen::MatrixXd& cand) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(model);
  double worst = 1.0;
  for (Eigen::Index c = 0; c < cand.cols(); ++c) {
    const Eigen::VectorXd col = cand.col(c);
    const Eigen::VectorXd resid = col - model * qr.solve(col);
    const double norm = col.norm();
    worst = std::min(worst, norm > 0 ? resid.norm() / norm : 0.0);
  }
  return worst;
}

struct Candidate {
  std::string name;
  int order = 0;
  Eigen::MatrixXd cols;
  std::string causes;
};

}  // namespace

OscillationDiagnosis diagnose_oscillation(const OscillationRecord& rec, const OscillationOptions& opt) {
  const std::size_t n_all = rec.t.size();
  require(rec.current.size() == n_all && rec.phi.size() == n_all, "record columns differ in length");
  const std::string where = rec.file.empty() ? std::string("record") : rec.file;
  const auto at_line = [&](std::size_t k) {
    std::string s = where;
    if (k < rec.lines.size()) {
      s += ':';
      s += std::to_string(rec.lines[k]);
    }
    s += ": ";
    return s;
  };
  require(std::isfinite(opt.kt) && opt.kt > 0 && opt.kt < 1e6,
          where + ": the torque constant K_T = " + num(opt.kt) +
              " N*m/A; expected a finite value in (0, 1e6) N*m/A");
  require(opt.derivative_window >= 5 && opt.derivative_window % 2 == 1, "derivative window must be odd and >= 5");
  const int m = opt.derivative_window / 2;
  require(n_all >= static_cast<std::size_t>(8 * opt.derivative_window),
          where + ": " + std::to_string(n_all) + " samples; expected at least " +
              std::to_string(8 * opt.derivative_window) + " (8 derivative windows of " +
              std::to_string(opt.derivative_window) + " samples)");
  // The sampling step: the median step (one bad step does not move it).
  std::vector<double> steps(n_all - 1);
  for (std::size_t k = 1; k < n_all; ++k) steps[k - 1] = rec.t[k] - rec.t[k - 1];
  std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2), steps.end());
  const double dt = steps[steps.size() / 2];
  require(dt > 0, where + ": time must increase (median step " + num(dt) + " s)");
  for (std::size_t k = 1; k < n_all; ++k) {
    const double step = rec.t[k] - rec.t[k - 1];
    require(std::abs(step - dt) < 1e-6 * dt + 1e-12,
            at_line(k) + "time must be uniformly sampled: step " + num(step) +
                " s, expected " + num(dt) + " s (the median step)");
  }
  // Savitzky-Golay quadratic: phi' = sum j phi_j / (S2 dt), phi'' = 2 c / dt^2.
  double s2 = 0, s4 = 0;
  for (int j = -m; j <= m; ++j) {
    s2 += j * j;
    s4 += static_cast<double>(j) * j * j * j;
  }
  const double w = 2 * m + 1;
  const std::size_t n = n_all - 2 * static_cast<std::size_t>(m);
  Eigen::VectorXd y(static_cast<Eigen::Index>(n)), phi(static_cast<Eigen::Index>(n)), rate(static_cast<Eigen::Index>(n)),
      acc(static_cast<Eigen::Index>(n)), tt(static_cast<Eigen::Index>(n));
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t c = k + static_cast<std::size_t>(m);
    double sj = 0, sj2 = 0, s0 = 0;
    for (int j = -m; j <= m; ++j) {
      const double v = rec.phi[static_cast<std::size_t>(static_cast<long>(c) + j)];
      s0 += v;
      sj += j * v;
      sj2 += j * j * v;
    }
    const auto e = static_cast<Eigen::Index>(k);
    rate[e] = sj / (s2 * dt);
    acc[e] = 2.0 * (w * sj2 - s2 * s0) / (w * s4 - s2 * s2) / (dt * dt);
    phi[e] = rec.phi[c];
    y[e] = opt.kt * rec.current[c];
    require(std::isfinite(y[e]), at_line(c) + "K_T i is not finite (K_T = " + num(opt.kt) +
                                     " N*m/A, i = " + num(rec.current[c]) + " A)");
    tt[e] = rec.t[c];
  }
  require(rate.cwiseAbs().maxCoeff() > 0.0, where + ": phi does not move: no oscillation to diagnose");
  // Direction of motion: the sign of the smoothed rate, a zero rate (quantised encoder at
  // rest for a window) taking the last nonzero sign (the first one for leading zeros).
  Eigen::VectorXd direction(static_cast<Eigen::Index>(n));
  {
    double last = 0.0;
    for (Eigen::Index k = 0; k < rate.size(); ++k) {
      if (rate[k] != 0.0) {
        last = rate[k] > 0 ? 1.0 : -1.0;
        break;
      }
    }
    for (Eigen::Index k = 0; k < rate.size(); ++k) {
      if (rate[k] != 0.0) last = rate[k] > 0 ? 1.0 : -1.0;
      direction[k] = last;
    }
  }
  OscillationDiagnosis out;
  out.n = n;
  out.torque_eq21 = opt.kt * std::accumulate(rec.current.begin(), rec.current.end(), 0.0) / static_cast<double>(n_all);
  const auto ne = static_cast<Eigen::Index>(n);
  // The spring term: gravity's pendulum stiffness m g e cos(theta + eps) plus any cable,
  // about the record's mean angle. It is the physics of the phi equation, so it is in the
  // base model whenever the motion separates it from the inertia.
  const double phimean = phi.mean();
  Eigen::MatrixXd model(ne, 4);
  model.col(0) = Eigen::VectorXd::Ones(ne);
  model.col(1) = acc;
  model.col(2) = rate;
  model.col(3) = direction;
  const Eigen::VectorXd spring = (phi.array() - phimean).matrix();
  // Below 5% of independent part the spring's SE would swamp J: lump it into J instead.
  const bool has_spring = independence(model, spring) >= 0.05;
  if (has_spring) {
    Eigen::MatrixXd grown(ne, 5);
    grown << model, spring;
    model = grown;
  } else {
    out.not_identifiable.emplace_back(
        "spring", "the motion is too purely sinusoidal to separate a spring (gravity's pendulum stiffness, "
                  "cable) from the inertia; it is lumped into J");
  }
  const Fit base = least_squares(model, y);
  const auto param = [](const Fit& f, Eigen::Index i, const char* name, const char* unit) {
    return OscillationParam{name, f.beta[i], std::sqrt(f.cov(i, i)), unit};
  };
  out.torque_before = param(base, 0, "M_0", "N*m");
  out.base_before = {param(base, 1, "J", "kg*m^2"), param(base, 2, "B", "N*m*s/rad"), param(base, 3, "C", "N*m")};
  if (has_spring) out.base_before.push_back(param(base, 4, "K", "N*m/rad"));
  out.rmse_before = std::sqrt(base.rss / static_cast<double>(n));

  const double tmean = tt.mean();
  std::vector<Candidate> fixed;
  fixed.push_back({"offset_drift", 0, (tt.array() - tmean).matrix(),
                   "current-sensor offset drift (amplifier warm-up), motor heating changing K_T"});
  fixed.push_back({"coulomb_asymmetry", 0, direction.unaryExpr([](double v) { return v > 0 ? 1.0 : 0.0; }),
                   "direction-dependent bearing friction (preload, lubricant, seal)"});
  // Cogging orders that complete one cycle over the swing; lower ones are not identifiable.
  const double swing = phi.maxCoeff() - phi.minCoeff();
  using angles::kTwoPi;
  const int min_order = std::max(opt.cogging_min_order,
                                 swing > 0 ? static_cast<int>(std::ceil(kTwoPi / swing - 1e-9)) : opt.cogging_max_order + 1);
  {
    char buf[600];
    const double swing_deg = swing * 180.0 / 3.141592653589793;
    if (min_order > opt.cogging_min_order) {
      std::snprintf(buf, sizeof buf,
                    "not identifiable with this swing (%.3g deg peak to peak) for orders %d to %d per turn: they "
                    "complete less than one cycle over the swing and trade off with the constant and the "
                    "spring. Order N needs a swing of at least 360/N deg (order %d: %.3g deg, i.e. +-%.3g deg)%s",
                    swing_deg, opt.cogging_min_order, std::min(min_order - 1, opt.cogging_max_order),
                    opt.cogging_min_order, 360.0 / opt.cogging_min_order, 180.0 / opt.cogging_min_order,
                    min_order <= opt.cogging_max_order ? "; orders from the swing's limit up are scanned" : "");
      out.not_identifiable.emplace_back("cogging", buf);
    }
  }
  const double plausible = 2.0 * std::sqrt(2.0) * out.rmse_before;  // largest amplitude the residual holds
  bool cogging_in = min_order > opt.cogging_max_order;
  std::vector<std::string> added;
  Fit cur = base;
  for (int round = 0; round < 8; ++round) {
    struct Tested {
      Candidate cand;
      double p, p_family, dbic;
      Fit fit;
    };
    std::vector<Tested> tested;
    const long p0 = model.cols();
    for (const auto& c : fixed) {
      if (std::find(added.begin(), added.end(), c.name) != added.end()) continue;
      if (independence(model, c.cols) < 1e-3) {
        if (round == 0) {
          out.not_identifiable.emplace_back(
              c.name, "a constant friction asymmetry is, at one position, the unbalance torque's alias: it "
                  "biases M_0 (and Eq. 21) by half the asymmetry; separate it with tests at two "
                  "oscillation centres or by comparing turntable directions");
        }
        continue;
      }
      Eigen::MatrixXd x(ne, p0 + c.cols.cols());
      x << model, c.cols;
      const Fit f = least_squares(x, y);
      const double p = f_test_p(cur.rss, f.rss, c.cols.cols(), static_cast<long>(n), x.cols());
      const double dbic = static_cast<double>(n) * std::log(f.rss / cur.rss) + static_cast<double>(c.cols.cols()) * std::log(static_cast<double>(n));
      tested.push_back({c, p, p, dbic, f});
    }
    if (!cogging_in) {  // scan the cogging order as one family
      // Fast scan: with Q an orthonormal basis of the model and r the current residual, the
      // RSS a candidate pair C removes is r' Ct (Ct' Ct)^-1 Ct' r, Ct = C - Q Q' C.
      Eigen::HouseholderQR<Eigen::MatrixXd> qr(model);
      const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(ne, model.cols());
      const Eigen::VectorXd r = y - model * cur.beta;
      int best_order = 0, count = 0;
      double best_drop = 0.0;  // compare by the RSS removed: p-values underflow to 0
      for (int order = min_order; order <= opt.cogging_max_order; ++order) {
        Eigen::MatrixXd cols(ne, 2);
        cols.col(0) = (order * phi.array()).sin().matrix();
        cols.col(1) = (order * phi.array()).cos().matrix();
        const Eigen::MatrixXd ct = cols - q * (q.transpose() * cols);
        if (ct.col(0).norm() < 1e-3 * cols.col(0).norm() || ct.col(1).norm() < 1e-3 * cols.col(1).norm()) continue;
        ++count;
        const Eigen::Matrix2d g = ct.transpose() * ct;
        const Eigen::Vector2d b = ct.transpose() * r;
        const double drop = b.dot(g.ldlt().solve(b));
        if (drop > best_drop) {
          best_drop = drop;
          best_order = order;
        }
      }
      if (count > 0 && best_order > 0) {
        Eigen::MatrixXd cols(ne, 2);
        cols.col(0) = (best_order * phi.array()).sin().matrix();
        cols.col(1) = (best_order * phi.array()).cos().matrix();
        Eigen::MatrixXd x(ne, p0 + 2);
        x << model, cols;
        const Fit f = least_squares(x, y);
        const double dbic = static_cast<double>(n) * std::log(f.rss / cur.rss) + 2.0 * std::log(static_cast<double>(n));
        const double best_p = f_test_p(cur.rss, f.rss, 2, static_cast<long>(n), x.cols());
        const double amp = std::hypot(f.beta[p0], f.beta[p0 + 1]);
        const int edge = min_order + std::max(2, min_order / 20);
        if (min_order > opt.cogging_min_order && best_order <= edge) {
          char buf[400];
          std::snprintf(buf, sizeof buf,
                        "the best order, %d, lies at the swing's limit (orders from %d are scanned): the "
                        "structure most likely belongs to a lower order that this swing cannot identify; "
                        "not added. A larger swing would test the lower orders",
                        best_order, min_order);
          out.not_identifiable.emplace_back("cogging", buf);
          cogging_in = true;
        } else if (amp > plausible) {
          char buf[300];
          std::snprintf(buf, sizeof buf,
                        "the best order, %d, fits an amplitude of %.3g N*m, more than the %.3g N*m the base "
                        "residual can hold (2 sqrt(2) x its RMS): it trades off with the base terms and is "
                        "refused as implausible",
                        best_order, amp, plausible);
          out.not_identifiable.emplace_back("cogging", buf);
          cogging_in = true;
        } else {
          tested.push_back({{"cogging", best_order, cols, "motor cogging (slot/pole detent) or a periodic drag of the bearing cage"},
                          best_p, std::min(1.0, best_p * count), dbic, f});
        }
      }
    }
    if (tested.empty()) break;
    // Holm across the round's candidates (each family counted once).
    std::vector<std::size_t> idx(tested.size());
    std::iota(idx.begin(), idx.end(), 0);
    std::sort(idx.begin(), idx.end(), [&](auto a, auto b) { return tested[a].p_family < tested[b].p_family; });
    const Tested& top = tested[idx[0]];
    const double p_adj = std::min(1.0, top.p_family * static_cast<double>(tested.size()));
    out.rounds = round + 1;
    if (!(p_adj < opt.alpha && top.dbic < 0)) break;
    OscillationEffect eff;
    eff.name = top.cand.name;
    eff.order = top.cand.order;
    eff.p_value = top.p;
    eff.p_adjusted = p_adj;
    eff.delta_bic = top.dbic;
    eff.causes = top.cand.causes;
    const Eigen::Index k0 = model.cols();
    if (eff.name == "cogging") {
      // Motor torque a sin(N phi) + b cos(N phi) = T sin(N phi + psi) balances a cogging
      // torque -T sin(N phi + psi).
      const double a = top.fit.beta[k0], b = top.fit.beta[k0 + 1];
      const double amp = std::hypot(a, b);
      const double va = top.fit.cov(k0, k0), vb = top.fit.cov(k0 + 1, k0 + 1), vab = top.fit.cov(k0, k0 + 1);
      const double se_amp = amp > 0 ? std::sqrt((a * a * va + 2 * a * b * vab + b * b * vb)) / amp : 0.0;
      const double se_ph = amp > 0 ? std::sqrt(b * b * va - 2 * a * b * vab + a * a * vb) / (amp * amp) : 0.0;
      eff.params = {{"amplitude", amp, se_amp, "N*m"}, {"phase", std::atan2(b, a), se_ph, "rad"}};
      cogging_in = true;
    } else {
      const char* unit = eff.name == "offset_drift" ? "N*m/s" : eff.name == "cable_stiffness" ? "N*m/rad" : "N*m";
      eff.params = {{eff.name == "offset_drift" ? "slope" : eff.name == "cable_stiffness" ? "stiffness" : "asymmetry",
                     top.fit.beta[k0], std::sqrt(top.fit.cov(k0, k0)), unit}};
      added.push_back(eff.name);
    }
    out.effects.push_back(eff);
    Eigen::MatrixXd grown(ne, k0 + top.cand.cols.cols());
    grown << model, top.cand.cols;
    model = grown;
    cur = top.fit;
  }
  out.torque_after = param(cur, 0, "M_0", "N*m");
  out.rmse_after = std::sqrt(cur.rss / static_cast<double>(n));
  return out;
}

}  // namespace poise::estimators
