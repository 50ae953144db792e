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

// The time stamps as they are: each must come after the one before (a repeated or backward
// stamp is an error naming its line). Returns the median step; gaps (a step of more than 5
// median steps) split the record into segments, each derived on its own.
struct TimeBase {
  double median_step = 0.0;
  std::vector<std::size_t> segment_starts;  ///< first row of each segment; the last ends at n
};

TimeBase time_base(const OscillationRecord& rec, const Where& w) {
  const std::size_t n = rec.t.size();
  for (std::size_t k = 1; k < n; ++k) {
    const double step = rec.t[k] - rec.t[k - 1];
    require(step > 0.0, w.at(k) + "time " + significant(rec.t[k], 9) + " s " +
                            (step == 0.0 ? "repeats the stamp of the row before"
                                         : "goes back from " + significant(rec.t[k - 1], 9) + " s") +
                            ": each row's time must come after the one before");
  }
  std::vector<double> steps(n - 1);
  for (std::size_t k = 1; k < n; ++k) steps[k - 1] = rec.t[k] - rec.t[k - 1];
  std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2), steps.end());
  TimeBase tb;
  tb.median_step = steps[steps.size() / 2];
  tb.segment_starts.push_back(0);
  for (std::size_t k = 1; k < n; ++k) {
    if (rec.t[k] - rec.t[k - 1] > 5.0 * tb.median_step) tb.segment_starts.push_back(k);
  }
  return tb;
}

// phi', phi'' at row c from the least-squares quadratic through rows [a, b] on their own times
// (on a uniform grid: the Savitzky-Golay filter).
std::pair<double, double> local_quadratic(const OscillationRecord& rec, std::size_t a, std::size_t b, std::size_t c) {
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d aty = Eigen::Vector3d::Zero();
  const double scale = std::max(rec.t[b] - rec.t[c], rec.t[c] - rec.t[a]);
  for (std::size_t j = a; j <= b; ++j) {
    const double u = (rec.t[j] - rec.t[c]) / scale;
    const Eigen::Vector3d row(1.0, u, u * u);
    ata += row * row.transpose();
    aty += row * rec.phi[j];
  }
  const Eigen::Vector3d coef = ata.ldlt().solve(aty);
  return {coef[1] / scale, 2.0 * coef[2] / (scale * scale)};
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
  require((rec.current.size() == n_all || rec.torque.size() == n_all) && rec.phi.size() == n_all &&
              (rec.velocity.empty() || rec.velocity.size() == n_all),
          "record columns differ in length");
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
  const TimeBase tb = time_base(rec, w);
  s.dt = tb.median_step;
  const bool by_torque = !rec.torque.empty();
  // Rows whose window lies within one segment (the window's edges dropped at each gap).
  std::vector<std::size_t> rows;
  for (std::size_t g = 0; g < tb.segment_starts.size(); ++g) {
    const std::size_t a = tb.segment_starts[g];
    const std::size_t b = g + 1 < tb.segment_starts.size() ? tb.segment_starts[g + 1] : n_all;
    for (std::size_t c = a + static_cast<std::size_t>(m); c + static_cast<std::size_t>(m) < b; ++c) rows.push_back(c);
  }
  require(rows.size() >= 8 * static_cast<std::size_t>(opt.derivative_window),
          w.file + ": " + std::to_string(rows.size()) + " samples lie in stretches without gaps of at least " +
              std::to_string(opt.derivative_window) + " samples; expected at least " +
              std::to_string(8 * opt.derivative_window));
  s.n = rows.size();
  const auto ne = static_cast<Eigen::Index>(s.n);
  s.y.resize(ne), s.phi.resize(ne), s.rate.resize(ne), s.acc.resize(ne), s.t.resize(ne);
  for (std::size_t k = 0; k < s.n; ++k) {
    const std::size_t c = rows[k];
    const auto [rate, acc] = local_quadratic(rec, c - static_cast<std::size_t>(m), c + static_cast<std::size_t>(m), c);
    const auto e = static_cast<Eigen::Index>(k);
    s.rate[e] = rec.velocity.empty() ? rate : rec.velocity[c];
    s.acc[e] = acc;
    s.phi[e] = rec.phi[c];
    s.y[e] = by_torque ? rec.torque[c] : opt.kt * rec.current[c];
    if (!std::isfinite(s.y[e])) {
      throw Error(w.at(c) + (by_torque ? "the torque is not finite"
                                       : "K_T i is not finite (K_T = " + significant(opt.kt, 6) +
                                             " N*m/A, i = " + significant(rec.current[c], 6) + " A)"));
    }
    s.t[e] = rec.t[c];
  }
  const auto [lowest, highest] = std::minmax_element(rec.phi.begin(), rec.phi.end());
  s.span_all = *highest - *lowest;
  s.gaps = tb.segment_starts.size() - 1;
  for (std::size_t g = 1; g < tb.segment_starts.size(); ++g) {
    const std::size_t k = tb.segment_starts[g];
    const double gap = rec.t[k] - rec.t[k - 1];
    s.gap_total += gap;
    if (gap > s.gap_largest) {
      s.gap_largest = gap;
      s.gap_largest_line = k < rec.lines.size() ? rec.lines[k] : k + 1;
    }
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
