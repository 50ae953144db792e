#include "estimators/residual_diagnosis_model.h"

#include <Eigen/QR>
#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/fisher_f.hpp>
#include <cmath>
#include <limits>

#include "core/format.h"

namespace poise::estimators::detail {
namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

// |R_ii| below this fraction of the largest pivot (columns scaled to unit norm): the columns
// are not separable at these points.
constexpr double kRankThreshold = 1e-10;

// P m in measurement order (identity for rho = 0), indexed by row.
MatrixXd whiten(const MatrixXd& m, const std::vector<std::size_t>& order, double rho) {
  if (rho == 0.0) return m;
  MatrixXd w(m.rows(), m.cols());
  const auto first = static_cast<Index>(order[0]);
  w.row(first) = std::sqrt(1.0 - rho * rho) * m.row(first);
  for (std::size_t k = 1; k < order.size(); ++k) {
    const auto i = static_cast<Index>(order[k]), j = static_cast<Index>(order[k - 1]);
    w.row(i) = m.row(i) - rho * m.row(j);
  }
  return w;
}

}  // namespace

LinearFit fit_linear(const MatrixXd& x, const ModelData& d, bool ar, double rho) {
  LinearFit f;
  const double r = ar ? rho : 0.0;
  const MatrixXd xw = whiten(x, d.order, r);
  const VectorXd yw = whiten(d.y, d.order, r);
  const VectorXd scale = xw.colwise().norm().transpose();
  if ((scale.array() <= 0.0).any()) return f;
  const Index p = x.cols();
  const MatrixXd xs = xw * scale.cwiseInverse().asDiagonal();
  Eigen::ColPivHouseholderQR<MatrixXd> qr(xs);
  qr.setThreshold(kRankThreshold);
  if (qr.rank() < p) return f;
  const VectorXd bs = qr.solve(yw);
  f.resid = yw - xs * bs;
  f.beta = bs.cwiseQuotient(scale);
  f.rss = f.resid.squaredNorm();
  f.dof = d.n - p - (ar ? 1 : 0);
  // (X^T X)^-1 = D^-1 P R^-1 R^-T P^T D^-1 with X D^-1 P = Q R; X^T X itself is never formed.
  const MatrixXd rr = qr.matrixR().topLeftCorner(p, p).triangularView<Eigen::Upper>();
  f.logdet = 2.0 * (rr.diagonal().array().abs().log().sum() + scale.array().log().sum());
  const MatrixXd r_inv = rr.triangularView<Eigen::Upper>().solve(MatrixXd::Identity(p, p));
  const MatrixXd l = scale.cwiseInverse().asDiagonal() * (qr.colsPermutation() * r_inv);
  f.cov = (f.rss / static_cast<double>(std::max<Index>(f.dof, 1))) * (l * l.transpose());
  f.ok = true;
  return f;
}

double restricted_loglik(const MatrixXd& x, const ModelData& d, double rho) {
  const LinearFit f = fit_linear(x, d, true, rho);
  if (!f.ok) return -std::numeric_limits<double>::infinity();
  return -0.5 * static_cast<double>(d.n - x.cols()) * std::log(std::max(f.rss, d.rss_floor)) +
         0.5 * std::log(1.0 - rho * rho) - 0.5 * f.logdet;
}

RhoFit fit_rho(const MatrixXd& x, const ModelData& d) {
  constexpr int kGrid = 41;  // step 0.0495, rho = 0 at the middle
  const auto at = [&](double r) { return restricted_loglik(x, d, r); };
  std::vector<double> grid(kGrid);
  int best = 0;
  double best_l = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < kGrid; ++k) {
    grid[k] = -kMaxRho + 2.0 * kMaxRho * k / (kGrid - 1);
    const double l = at(grid[k]);
    if (l > best_l) best_l = l, best = k;
  }
  // Golden section inside the grid cells either side of the best grid point.
  double lo = grid[std::max(best - 1, 0)], hi = grid[std::min(best + 1, kGrid - 1)];
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), l1 = at(x1), l2 = at(x2);
  for (int it = 0; it < 60 && hi - lo > 1e-9; ++it) {
    if (l1 > l2) {
      hi = x2, x2 = x1, l2 = l1, x1 = hi - g * (hi - lo), l1 = at(x1);
    } else {
      lo = x1, x1 = x2, l1 = l2, x2 = lo + g * (hi - lo), l2 = at(x2);
    }
  }
  RhoFit rf;
  rf.rho = 0.5 * (lo + hi);
  rf.loglik = at(rf.rho);
  if (best_l > rf.loglik) rf.rho = grid[best], rf.loglik = best_l;
  // Observed information by a central difference; the asymptotic (1 - rho^2) / n otherwise.
  const double h = 1e-3, c = std::clamp(rf.rho, -kMaxRho + h, kMaxRho - h);
  const double curv = (at(c + h) - 2.0 * at(c) + at(c - h)) / (h * h);
  rf.se = curv < 0.0 ? 1.0 / std::sqrt(-curv) : std::sqrt((1.0 - rf.rho * rf.rho) / static_cast<double>(d.n));
  return rf;
}

MatrixXd with_columns(const MatrixXd& x, const MatrixXd& add) {
  MatrixXd out(x.rows(), x.cols() + add.cols());
  out << x, add;
  return out;
}

// F test and delta_BIC of adding t.cols to the model; false if not examinable. With AR(1)
// errors both models are fitted at the rho of the larger one: a smooth effect is then not
// tested against errors whose rho already absorbed it.
bool nested_test(const Model& m, const ModelData& d, Term& t, bool refit_rho) {
  const Index p1 = m.x.cols() + t.cols.cols(), q = t.cols.cols();
  if (d.n - p1 - (m.ar ? 1 : 0) < kMinResidualDof) {
    t.note = "not examined: would leave fewer than 5 residual degrees of freedom";
    return false;
  }
  const MatrixXd x1 = with_columns(m.x, t.cols);
  const double rho = !m.ar ? 0.0 : refit_rho ? fit_rho(x1, d).rho : m.rho.rho;
  const LinearFit f1 = fit_linear(x1, d, m.ar, rho);
  if (!f1.ok) {
    t.note = "not examined: not separable from the model's columns at these points";
    return false;
  }
  const LinearFit f0 = fit_linear(m.x, d, m.ar, rho);
  const double rss0 = std::max(f0.rss, d.rss_floor), rss1 = std::max(f1.rss, d.rss_floor);
  const double fstat = ((rss0 - rss1) / static_cast<double>(q)) / (rss1 / static_cast<double>(f1.dof));
  const boost::math::fisher_f dist(static_cast<double>(q), static_cast<double>(f1.dof));
  t.p = fstat > 0.0 ? boost::math::cdf(boost::math::complement(dist, fstat)) : 1.0;
  const double n = static_cast<double>(d.n);
  t.delta_bic = n * std::log(rss1 / rss0) + static_cast<double>(q) * std::log(n);
  return t.examined = true;
}

// Outlier family: every point not yet flagged gets its indicator's F test (= squared
// externally studentized residual); the family is the largest, Bonferroni-adjusted.
Term outlier_family(const Model& m, const ModelData& d) {
  Term best("outlier", "outlier");
  double best_p = 2.0;
  int tested = 0;
  for (Index i = 0; i < d.n; ++i) {
    const bool flagged =
        std::any_of(m.terms.begin(), m.terms.end(), [&](const Term& t) { return t.index == static_cast<int>(i); });
    if (flagged) continue;
    Term t("outlier", "outlier", 0, static_cast<int>(i));
    t.cols = MatrixXd::Zero(d.n, 1);
    t.cols(i, 0) = 1.0;
    if (!nested_test(m, d, t)) continue;
    ++tested;
    if (t.p < best_p) best_p = t.p, best = t;
  }
  if (tested == 0) {
    best.note = "not examined: no point can be tested";
    return best;
  }
  best.p = std::min(1.0, tested * best.p);
  best.note =
      "largest at row " + std::to_string(best.index) + ", Bonferroni over " + std::to_string(tested) + " points";
  return best;
}

// LR test of AR(1) errors against the current (OLS) model.
Term autocorrelation_test(const Model& m, const ModelData& d) {
  Term t("autocorrelation", "autocorrelation");
  if (d.n - m.x.cols() - 1 < kMinResidualDof) {
    t.note = "not examined: would leave fewer than 5 residual degrees of freedom";
    return t;
  }
  if (fit_linear(m.x, d, false, 0.0).rss <= d.rss_floor) {
    t.note = "not examined: the residuals are zero to rounding";
    return t;
  }
  const RhoFit rf = fit_rho(m.x, d);
  const double n = static_cast<double>(d.n);
  const double l0 = restricted_loglik(m.x, d, 0.0);
  const double lr = std::max(0.0, 2.0 * (rf.loglik - l0));
  // One-sided, against positive correlation (the signed root of the LR is asymptotically
  // normal): drifts, thermal lag and a servo's slow error correlate successive readings
  // positively; a negative rho is not an error law a measurement in time produces, and where
  // the residual alternates a deterministic term (a direction offset) is the candidate.
  const double two_sided = boost::math::cdf(boost::math::complement(boost::math::chi_squared(1.0), lr));
  t.p = rf.rho > 0.0 ? 0.5 * two_sided : 1.0 - 0.5 * two_sided;
  t.delta_bic = -lr + std::log(n);
  t.note = fmt::format("rho = {:.3f}", rf.rho);
  t.examined = true;
  return t;
}

// Holm step-down adjustment of the examined candidates' p.
void holm(std::vector<Term>& c) {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c[i].examined) idx.push_back(i);
  }
  std::stable_sort(idx.begin(), idx.end(), [&](auto a, auto b) { return c[a].p < c[b].p; });
  double running = 0.0;
  for (std::size_t j = 0; j < idx.size(); ++j) {
    running = std::max(running, std::min(1.0, static_cast<double>(idx.size() - j) * c[idx[j]].p));
    c[idx[j]].p_adj = running;
  }
}

std::string describe(const Term& t) {
  if (!t.examined) return t.label + ": " + t.note;
  const std::string stats =
      fmt::format("p = {:.3g}, Holm-adjusted p = {:.3g}, delta_BIC = {:+.2f}", t.p, t.p_adj, t.delta_bic);
  return t.label + (t.note.empty() ? "" : " (" + t.note + ")") + ": " + stats;
}

}  // namespace poise::estimators::detail
