#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/angles.h"
#include "core/format.h"
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
  r.min_order =
      std::max(opt.cogging_min_order, swing > 0 ? static_cast<int>(std::ceil(kTwoPi / swing - 1e-9)) : r.max_order + 1);
  r.limited_by_swing = r.min_order > opt.cogging_min_order;
  if (r.limited_by_swing) {
    out.not_identifiable.emplace_back(
        "cogging",
        fmt::format("not identifiable with this swing ({:.3g} deg peak to peak) for orders {} to {} per turn: they "
                    "complete less than one cycle over the swing and trade off with the constant and the "
                    "spring. Order N needs a swing of at least 360/N deg (order {}: {:.3g} deg, i.e. +-{:.3g} deg){}",
                    swing * 180.0 / kPi, opt.cogging_min_order, std::min(r.min_order - 1, r.max_order),
                    opt.cogging_min_order, 360.0 / opt.cogging_min_order, 180.0 / opt.cogging_min_order,
                    r.min_order <= r.max_order ? "; orders from the swing's limit up are scanned" : ""));
  }
  return r;
}

// Fast scan (the RSS each order removes): with Q an orthonormal basis of the model and r the current residual (Q^T r =
// 0), the RSS that the pair C = [sin N phi, cos N phi] removes is b^T G^-1 b with b = C^T r and G = C^T C - (Q^T C)^T
// (Q^T C). One pass over the samples per order: sin and cos of N phi by the angle-addition recurrence (restarted
// exactly every 64 orders: its rounding grows like N eps), the sums of b, C^T C and Q^T C accumulated together.
OrderScan scan_orders(const Eigen::MatrixXd& model, const Eigen::VectorXd& resid, const Eigen::VectorXd& phi,
                      const OrderRange& range) {
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
      for (Eigen::Index j = 0; j < p; ++j)
        qs[static_cast<std::size_t>(j)] += qk[j] * sv, qc[static_cast<std::size_t>(j)] += qk[j] * cv;
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
// log of the survival function of F(2, d2): -(d2 / 2) log(1 + 2 F / d2) (in logs: the p of a
// strong cogging underflows).
double f2_log_sf(double f, double d2) { return f <= 0 ? 0.0 : -0.5 * d2 * std::log1p(2.0 * f / d2); }

double median_of(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return *mid;
  return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

// The local level about drop[i]: the median of the neighbours' drops / (2 ln 2), and the
// independent cells it rests on (level 0 with fewer than 2 cells).
struct Level {
  double sigma2 = 0.0, cells = 0.0;
};
Level local_level(const OrderScan& scan, long i, double cell, double local_cells) {
  const auto n = static_cast<long>(scan.drop.size());
  const long guard = std::lround(kGuardCells * cell), width = std::lround(local_cells * cell);
  // At an end of the scan the window keeps its size, shifted inward.
  const long lo = std::clamp(i - guard - width, 0L, std::max(0L, n - 1 - 2 * (guard + width)));
  std::vector<double> nb;
  for (long j = lo; j < n && j <= lo + 2 * (guard + width); ++j) {
    const double v = scan.drop[static_cast<std::size_t>(j)];
    if (std::abs(j - i) >= guard && std::isfinite(v)) nb.push_back(v);
  }
  Level l;
  l.cells = static_cast<double>(nb.size()) / std::max(1.0, cell);
  if (l.cells >= 2.0) l.sigma2 = median_of(std::move(nb)) / (2.0 * std::log(2.0));
  return l;
}

// A drop judged against the larger of the white level (F(2, dof_white)) and the local one.
LocalTest judge(double drop, double white, double dof_white, const Level& local) {
  LocalTest t;
  t.sigma2 = white, t.dof = dof_white;
  t.white = !(local.sigma2 > white);
  if (!t.white) t.sigma2 = local.sigma2, t.dof = 2.0 * local.cells;
  if (!(t.sigma2 > 0) || !(drop > 0)) return t;
  t.f = drop / (2.0 * t.sigma2);
  t.log_p = f2_log_sf(t.f, t.dof);
  return t;
}

// The index of the smallest p with the scan's own levels (the pair of each order not removed;
// rss, dof: the model's fit the scan was run on).
long nominated(const OrderScan& scan, double cell, double rss, double dof, double local_cells, const OrderScan* noise) {
  long at = -1;
  double best = 0.0;
  for (long i = 0; i < static_cast<long>(scan.drop.size()); ++i) {
    const double d = scan.drop[static_cast<std::size_t>(i)];
    if (!std::isfinite(d)) continue;
    const LocalTest t =
        judge(d, (rss - d) / (dof - 2.0), dof - 2.0, local_level(noise ? *noise : scan, i, cell, local_cells));
    if (t.f > 0 && (at < 0 || t.log_p < best)) best = t.log_p, at = i;
  }
  return at;
}

// The index of the largest drop within `reach` of i (the whole scan when reach < 0).
long largest(const OrderScan& scan, long i, long reach) {
  const auto n = static_cast<long>(scan.drop.size());
  long top = -1;
  for (long j = reach < 0 ? 0 : std::max(0L, i - reach); j < n && (reach < 0 || j <= i + reach); ++j) {
    const double v = scan.drop[static_cast<std::size_t>(j)];
    if (std::isfinite(v) && (top < 0 || v > scan.drop[static_cast<std::size_t>(top)])) top = j;
  }
  return top;
}

// The order's test with its pair in the model (fitted on y): the local level from the drops of
// its neighbours on the residual the pair leaves (a strong order's own side lobes would raise
// it), the white level that residual's.
LocalTest judged(const Eigen::MatrixXd& model, const Eigen::VectorXd& y, const Eigen::VectorXd& phi,
                 const OrderRange& range, double cell, int order, double rss, double local_cells,
                 const OrderScan* noise) {
  const Eigen::MatrixXd x = joined(model, cogging_columns(phi, order));
  const Fit fit = least_squares(x, y);
  const int reach = static_cast<int>(std::lround((kGuardCells + local_cells) * cell));
  OrderRange near = range;
  near.max_order = std::min(range.max_order, std::max(order, range.min_order + reach) + reach);
  near.min_order = std::max(range.min_order, near.max_order - 2 * reach);
  const OrderScan scan = scan_orders(x, y - x * fit.beta, phi, near);
  const auto dof = static_cast<double>(y.size() - x.cols());
  const Level level = noise ? local_level(*noise, order - range.min_order, cell, local_cells)
                            : local_level(scan, order - near.min_order, cell, local_cells);
  LocalTest t = judge(rss - fit.rss, fit.rss / dof, dof, level);
  t.order = order;
  return t;
}
}  // namespace

ScanBest scan_best(const Eigen::MatrixXd& model, const Eigen::VectorXd& y, const Eigen::VectorXd& phi,
                   const OrderRange& range, double cell, double local_cells, const OrderScan* noise) {
  ScanBest b;
  const Eigen::Index dof = y.size() - model.cols();
  if (dof <= 3) return b;
  const Fit fit = least_squares(model, y);
  const OrderScan scan = scan_orders(model, y - model * fit.beta, phi, range);
  b.count = scan.count;
  if (scan.count == 0) return b;
  // The orders judged: the smallest p with the scan's own levels (the whitened matched filter)
  // and the largest drop of all. Where the first's level, its pair removed, is the white one
  // (it was raised only by its own side lobes), it moves to the largest drop within a cell:
  // the least-squares order of its peak.
  long at = nominated(scan, cell, fit.rss, static_cast<double>(dof), local_cells, noise);
  const long top = largest(scan, 0, -1);
  for (const long i : {at, top}) {
    if (i < 0 || (i == top && at == top && b.test.order != 0)) continue;
    LocalTest t = judged(model, y, phi, range, cell, scan.first + static_cast<int>(i), fit.rss, local_cells, noise);
    if (i == at && t.white) {
      const long peak = largest(scan, at, std::max(1L, std::lround(cell)));
      if (peak != at) {
        t = judged(model, y, phi, range, cell, scan.first + static_cast<int>(peak), fit.rss, local_cells, noise);
        at = peak;
      }
    }
    if (t.f > 0 && (b.test.order == 0 || t.log_p < b.test.log_p)) b.test = t;
  }
  return b;
}

namespace {
// The pick of one scan, and whether it lies at its range's swing limit.
CoggingPick scanned(const Eigen::MatrixXd& model, const Eigen::VectorXd& y, const Eigen::VectorXd& phi,
                    const OrderRange& range, bool limited) {
  CoggingPick c;
  const double swing = phi.size() > 0 ? phi.maxCoeff() - phi.minCoeff() : 0.0;
  if (!(swing > 0)) return c;
  const ScanBest b = scan_best(model, y, phi, range, angles::kTwoPi / swing);
  c.test = b.test, c.count = b.count, c.resolution = angles::kPi / swing;
  c.at_edge = limited && c.test.order != 0 && c.test.order <= range.min_order + std::max(2, range.min_order / 20);
  return c;
}
}  // namespace

CoggingPick pick_cogging(const Signals& s, const Eigen::MatrixXd& model, const Moving& mv, const OrderRange& range) {
  CoggingPick whole = scanned(model, s.y, s.phi, range, range.limited_by_swing);
  OrderRange near = range;
  const double swing = mv.phi.size() > 0 ? mv.phi.maxCoeff() - mv.phi.minCoeff() : 0.0;
  if (swing > 0) near.min_order = std::max(range.min_order, static_cast<int>(std::ceil(angles::kTwoPi / swing - 1e-9)));
  CoggingPick moving =
      scanned(mv.model, mv.y, mv.phi, near, range.limited_by_swing || near.min_order > range.min_order);
  moving.on_moving = true;
  const int count = whole.count + moving.count;
  // The swing limit is the whole record's: there a pick at it is refused; the moving samples'
  // narrower swing has a limit of its own, where their pick is not taken.
  const bool take_moving = moving.test.order != 0 && !moving.at_edge && !whole.at_edge &&
                           (whole.test.order == 0 || moving.test.log_p < whole.test.log_p);
  CoggingPick& pick = take_moving ? moving : whole;
  pick.count = count;
  return pick;
}

}  // namespace poise::estimators::osc
