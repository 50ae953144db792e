#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "core/angles.h"
#include "estimators/oscillation_detail.h"

namespace poise::estimators::osc {
namespace {
constexpr int kProjectedCycles = 16;
}  // namespace

Eigen::MatrixXd cogging_columns(const Eigen::VectorXd& phi, int order) {
  Eigen::MatrixXd cols(phi.size(), 2);
  cols.col(0) = (order * phi.array()).sin().matrix();
  cols.col(1) = (order * phi.array()).cos().matrix();
  return cols;
}

OrderRange cogging_orders(const Signals& s, const OscillationOptions& opt, OscillationDiagnosis& out) {
  using angles::kPi;
  using angles::kTwoPi;
  const double swing = s.phi.maxCoeff() - s.phi.minCoeff();
  // Nyquist: the cogging frequency N |phi'| / (2 pi) stays below half the sample rate.
  const double top_rate = s.rate.cwiseAbs().maxCoeff();
  const double nyquist = top_rate > 0.0 ? kPi / (top_rate * s.dt) : 0.0;
  OrderRange r;
  r.max_order = static_cast<int>(std::min(nyquist, 1e6));
  if (opt.cogging_max_order > 0) r.max_order = std::min(r.max_order, opt.cogging_max_order);
  r.min_order = std::max(opt.cogging_min_order,
                         swing > 0 ? static_cast<int>(std::ceil(kTwoPi / swing - 1e-9)) : r.max_order + 1);
  r.limited_by_swing = r.min_order > opt.cogging_min_order;
  if (r.limited_by_swing) {
    char buf[600];
    std::snprintf(buf, sizeof buf,
                  "not identifiable with this swing (%.3g deg peak to peak) for orders %d to %d per turn: they "
                  "complete less than one cycle over the swing and trade off with the constant and the "
                  "spring. Order N needs a swing of at least 360/N deg (order %d: %.3g deg, i.e. +-%.3g deg)%s",
                  swing * 180.0 / kPi, opt.cogging_min_order, std::min(r.min_order - 1, r.max_order),
                  opt.cogging_min_order, 360.0 / opt.cogging_min_order, 180.0 / opt.cogging_min_order,
                  r.min_order <= r.max_order ? "; orders from the swing's limit up are scanned" : "");
    out.not_identifiable.emplace_back("cogging", buf);
  }
  return r;
}

// Fast scan (the RSS each order removes): with Q an orthonormal basis of the model and r the current residual (Q^T r = 0),
// the RSS that the pair C = [sin N phi, cos N phi] removes is b^T G^-1 b with b = C^T r and
// G = C^T C - (Q^T C)^T (Q^T C). One pass over the samples per order: sin and cos of N phi by
// the angle-addition recurrence (restarted exactly every 64 orders: its rounding grows like
// N eps), the sums of b, C^T C and Q^T C accumulated together.
OrderScan scan_orders(const Eigen::MatrixXd& model, const Eigen::VectorXd& resid,
                      const Eigen::VectorXd& phi, const OrderRange& range) {
  OrderScan scan;
  if (range.min_order > range.max_order) return scan;
  scan.first = range.min_order;
  scan.drop.assign(static_cast<std::size_t>(range.max_order - range.min_order + 1),
                   std::numeric_limits<double>::quiet_NaN());
  const Eigen::Index n = phi.size(), p = model.cols();
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(model);
  // Row-major copy of Q: one sample's p values side by side.
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> q =
      qr.householderQ() * Eigen::MatrixXd::Identity(n, p);
  const Eigen::ArrayXd s1 = phi.array().sin(), c1 = phi.array().cos();
  Eigen::ArrayXd sn(n), cn(n);
  std::vector<double> qs(static_cast<std::size_t>(p)), qc(static_cast<std::size_t>(p));
  for (int order = range.min_order; order <= range.max_order; ++order) {
    const bool restart = (order - range.min_order) % 64 == 0;
    if (restart) sn = (order * phi.array()).sin(), cn = (order * phi.array()).cos();
    // Past kProjectedCycles cycles over the swing the pair is orthogonal to the smooth base
    // columns to within a few 1e-3 of its norm: the projection is skipped in the scan (the
    // order picked is then tested exactly).
    const bool project = order < kProjectedCycles * range.min_order;
    double bs = 0, bc = 0, ss = 0, sc = 0, cc = 0;
    std::fill(qs.begin(), qs.end(), 0.0), std::fill(qc.begin(), qc.end(), 0.0);
    for (Eigen::Index k = 0; k < n; ++k) {
      double sv = sn[k], cv = cn[k];
      if (!restart) {
        const double s_next = sv * c1[k] + cv * s1[k];
        cv = cv * c1[k] - sv * s1[k], sv = s_next;
        sn[k] = sv, cn[k] = cv;
      }
      const double r = resid[k];
      bs += sv * r, bc += cv * r, ss += sv * sv, sc += sv * cv, cc += cv * cv;
      if (!project) continue;
      const double* qk = q.data() + k * p;
      for (Eigen::Index j = 0; j < p; ++j) qs[static_cast<std::size_t>(j)] += qk[j] * sv, qc[static_cast<std::size_t>(j)] += qk[j] * cv;
    }
    Eigen::Matrix2d g;
    g << ss, sc, sc, cc;
    for (std::size_t j = 0; j < qs.size(); ++j) {
      g(0, 0) -= qs[j] * qs[j], g(0, 1) -= qs[j] * qc[j], g(1, 1) -= qc[j] * qc[j];
    }
    g(1, 0) = g(0, 1);
    // A pair (numerically) in the model's span cannot be examined.
    if (g(0, 0) < 1e-6 * ss || g(1, 1) < 1e-6 * cc) continue;
    ++scan.count;
    const Eigen::Vector2d b(bs, bc);
    scan.drop[static_cast<std::size_t>(order - range.min_order)] = b.dot(g.ldlt().solve(b));
  }
  return scan;
}

Moving away_from_reversals(const Signals& s, const Eigen::MatrixXd& model) {
  const double limit = kMovingFraction * s.rate.cwiseAbs().maxCoeff();
  std::vector<Eigen::Index> keep;
  for (Eigen::Index k = 0; k < s.rate.size(); ++k) {
    if (std::abs(s.rate[k]) >= limit) keep.push_back(k);
  }
  const auto m = static_cast<Eigen::Index>(keep.size());
  Moving mv{Eigen::MatrixXd(m, model.cols()), Eigen::VectorXd(m), Eigen::VectorXd(m)};
  for (Eigen::Index i = 0; i < m; ++i) {
    const Eigen::Index k = keep[static_cast<std::size_t>(i)];
    mv.model.row(i) = model.row(k), mv.y[i] = s.y[k], mv.phi[i] = s.phi[k];
  }
  return mv;
}

namespace {
// Survival function of F(2, d2): (1 + 2 F / d2)^(-d2 / 2).
double f2_sf(double f, double d2) { return f <= 0 ? 1.0 : std::exp(-0.5 * d2 * std::log1p(2.0 * f / d2)); }

double median_of(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return *mid;
  return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}
}  // namespace

LocalTest best_local_order(const OrderScan& scan, double cell, double white_var, double dof_white) {
  LocalTest best;
  const auto n = static_cast<long>(scan.drop.size());
  const long guard = std::lround(kGuardCells * cell), width = std::lround(kLocalCells * cell);
  std::vector<double> nb;
  for (long i = 0; i < n; ++i) {
    const double d = scan.drop[static_cast<std::size_t>(i)];
    if (!std::isfinite(d)) continue;
    nb.clear();
    for (long j = std::max(0L, i - guard - width); j < n && j <= i + guard + width; ++j) {
      const double v = scan.drop[static_cast<std::size_t>(j)];
      if (std::abs(j - i) >= guard && std::isfinite(v)) nb.push_back(v);
    }
    const double cells = static_cast<double>(nb.size()) / std::max(1.0, cell);
    LocalTest t;
    t.order = scan.first + static_cast<int>(i);
    if (cells >= 2.0) {
      t.sigma2 = median_of(nb) / (2.0 * std::log(2.0)), t.dof = 2.0 * cells;
    } else {
      t.sigma2 = white_var, t.dof = dof_white;
    }
    if (!(t.sigma2 > 0)) continue;
    t.f = d / (2.0 * t.sigma2);
    t.p = f2_sf(t.f, t.dof);
    if (best.order == 0 || t.p < best.p || (t.p == best.p && t.f > best.f)) best = t;
  }
  return best;
}

}  // namespace poise::estimators::osc
