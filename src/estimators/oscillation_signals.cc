#include <algorithm>
#include <boost/math/distributions/fisher_f.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/format.h"
#include "estimators/oscillation_detail.h"

namespace poise::estimators::osc {
namespace {

struct Where {
  const OscillationRecord& rec;
  std::string file;
  std::string at(std::size_t k) const {
    std::string s = file;
    if (k < rec.lines.size()) s += ':' + std::to_string(rec.lines[k]);
    return s + ": ";
  }
};

// The sampling step: the median step (one bad step does not move it); every step must match.
double uniform_step(const OscillationRecord& rec, const Where& w) {
  const std::size_t n = rec.t.size();
  std::vector<double> steps(n - 1);
  for (std::size_t k = 1; k < n; ++k) steps[k - 1] = rec.t[k] - rec.t[k - 1];
  std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2), steps.end());
  const double dt = steps[steps.size() / 2];
  require(dt > 0, w.file + ": time must increase (median step " + significant(dt, 6) + " s)");
  for (std::size_t k = 1; k < n; ++k) {
    const double step = rec.t[k] - rec.t[k - 1];
    require(std::abs(step - dt) < 1e-6 * dt + 1e-12, w.at(k) + "time must be uniformly sampled: step " +
                                                         significant(step, 6) + " s, expected " + significant(dt, 6) +
                                                         " s (the median step)");
  }
  return dt;
}

// Direction of motion: the sign of the smoothed rate, a zero rate (quantised encoder at rest
// for a window) taking the last nonzero sign (the first one for leading zeros).
Eigen::VectorXd direction_of(const Eigen::VectorXd& rate) {
  Eigen::VectorXd d(rate.size());
  double last = 0.0;
  for (Eigen::Index k = 0; k < rate.size(); ++k) {
    if (rate[k] != 0.0) {
      last = rate[k] > 0 ? 1.0 : -1.0;
      break;
    }
  }
  for (Eigen::Index k = 0; k < rate.size(); ++k) {
    if (rate[k] != 0.0) last = rate[k] > 0 ? 1.0 : -1.0;
    d[k] = last;
  }
  return d;
}

}  // namespace

Signals derive_signals(const OscillationRecord& rec, const OscillationOptions& opt) {
  const std::size_t n_all = rec.t.size();
  require(rec.current.size() == n_all && rec.phi.size() == n_all, "record columns differ in length");
  const Where w{rec, rec.file.empty() ? std::string("record") : rec.file};
  require(std::isfinite(opt.kt) && opt.kt > 0 && opt.kt < 1e6,
          w.file + ": the torque constant K_T = " + significant(opt.kt, 6) +
              " N*m/A; expected a finite value in (0, 1e6) N*m/A");
  require(opt.derivative_window >= 5 && opt.derivative_window % 2 == 1, "derivative window must be odd and >= 5");
  const int m = opt.derivative_window / 2;
  require(n_all >= 8 * static_cast<std::size_t>(opt.derivative_window),
          w.file + ": " + std::to_string(n_all) + " samples; expected at least " +
              std::to_string(8 * opt.derivative_window) + " (8 derivative windows of " +
              std::to_string(opt.derivative_window) + " samples)");
  Signals s;
  s.dt = uniform_step(rec, w);
  // Savitzky-Golay quadratic: phi' = sum j phi_j / (S2 dt), phi'' = 2 c / dt^2.
  double s2 = 0, s4 = 0;
  for (int j = -m; j <= m; ++j) s2 += j * j, s4 += static_cast<double>(j) * j * j * j;
  const double wn = 2 * m + 1;
  s.n = n_all - 2 * static_cast<std::size_t>(m);
  const auto ne = static_cast<Eigen::Index>(s.n);
  s.y.resize(ne), s.phi.resize(ne), s.rate.resize(ne), s.acc.resize(ne), s.t.resize(ne);
  for (std::size_t k = 0; k < s.n; ++k) {
    const std::size_t c = k + static_cast<std::size_t>(m);
    double sj = 0, sj2 = 0, s0 = 0;
    for (int j = -m; j <= m; ++j) {
      const double v = rec.phi[static_cast<std::size_t>(static_cast<long>(c) + j)];
      s0 += v, sj += j * v, sj2 += j * j * v;
    }
    const auto e = static_cast<Eigen::Index>(k);
    s.rate[e] = sj / (s2 * s.dt);
    s.acc[e] = 2.0 * (wn * sj2 - s2 * s0) / (wn * s4 - s2 * s2) / (s.dt * s.dt);
    s.phi[e] = rec.phi[c];
    s.y[e] = opt.kt * rec.current[c];
    require(std::isfinite(s.y[e]), w.at(c) + "K_T i is not finite (K_T = " + significant(opt.kt, 6) +
                                       " N*m/A, i = " + significant(rec.current[c], 6) + " A)");
    s.t[e] = rec.t[c];
  }
  require(s.rate.cwiseAbs().maxCoeff() > 0.0, w.file + ": phi does not move: no oscillation to diagnose");
  s.direction = direction_of(s.rate);
  return s;
}

Fit least_squares(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(x);
  Fit f;
  f.beta = qr.solve(y);
  f.rss = (y - x * f.beta).squaredNorm();
  const double dof = static_cast<double>(x.rows() - x.cols());
  f.cov = (x.transpose() * x).inverse() * (f.rss / std::max(1.0, dof));
  return f;
}

double f_test_p(double rss0, double rss1, long q, long n, long p1) {
  if (!std::isfinite(rss0) || !std::isfinite(rss1) || rss1 <= 0 || rss0 <= rss1 || n - p1 < 1) return 1.0;
  const double f = ((rss0 - rss1) / static_cast<double>(q)) / (rss1 / static_cast<double>(n - p1));
  const boost::math::fisher_f dist(static_cast<double>(q), static_cast<double>(n - p1));
  return boost::math::cdf(boost::math::complement(dist, f));
}

double independence(const Eigen::MatrixXd& model, const Eigen::MatrixXd& cand) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(model);
  double worst = 1.0;
  for (Eigen::Index c = 0; c < cand.cols(); ++c) {
    const Eigen::VectorXd col = cand.col(c);
    const double norm = col.norm();
    worst = std::min(worst, norm > 0 ? (col - model * qr.solve(col)).norm() / norm : 0.0);
  }
  return worst;
}

Eigen::MatrixXd joined(const Eigen::MatrixXd& model, const Eigen::MatrixXd& cols) {
  Eigen::MatrixXd x(model.rows(), model.cols() + cols.cols());
  x << model, cols;
  return x;
}

}  // namespace poise::estimators::osc
