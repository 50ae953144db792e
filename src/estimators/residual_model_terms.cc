// The selected model's terms as the assessment and the guard use them: the estimate of a model,
// its BIC, a term dropped or added, the drop-one F test, the labels (residual_assessment.h).
#include <Eigen/QR>
#include <algorithm>
#include <array>
#include <boost/math/distributions/fisher_f.hpp>
#include <cmath>

#include "core/angles.h"
#include "core/format.h"
#include "estimators/residual_assessment.h"

namespace poise::estimators::detail {

using angles::wrap_two_pi;
using Eigen::Index;
using Eigen::MatrixXd;

// Drop-one F test p of term i in model m (OLS or GLS at m's rho).
double drop_one_p(const Model& m, const ModelData& d, std::size_t i) {
  const Term& t = m.terms[i];
  if (t.cols.cols() == 0) return t.p;
  const Model r = without_term(m, i);
  const LinearFit f1 = fit_linear(m.x, d, m.ar, m.rho.rho), f0 = fit_linear(r.x, d, m.ar, m.rho.rho);
  if (!f1.ok || !f0.ok || f1.dof < 1 || !(f1.rss > 0.0)) return 0.0;
  const double q = static_cast<double>(t.cols.cols());
  const double fs = std::max(0.0, (f0.rss - f1.rss) / q) / (f1.rss / static_cast<double>(f1.dof));
  return boost::math::cdf(boost::math::complement(boost::math::fisher_f(q, static_cast<double>(f1.dof)), fs));
}

std::string term_label(const Term& t) {
  if (t.name == "outlier") return "outlier at row " + std::to_string(t.index);
  if (t.name == "step") return "step before row " + std::to_string(t.index);
  if (t.name == "exponential_drift") return fmt::format("exponential_drift (tau {:.3g})", t.param);
  return t.label;
}

bool is_time_like(const std::string& n) {
  return n == "time_drift" || n == "time_drift_quadratic" || n == "exponential_drift" || n == "step" ||
         n == "kt_drift" || n == "autocorrelation";
}

double model_bic(const Model& m, const ModelData& d) {
  const LinearFit f = fit_linear(m.x, d, m.ar, m.rho.rho);
  if (!f.ok) return std::numeric_limits<double>::infinity();
  const double n = static_cast<double>(d.n);
  const double loglik = -0.5 * n * std::log(std::max(f.rss, d.rss_floor) / n) +
                        (m.ar ? 0.5 * std::log(1.0 - m.rho.rho * m.rho.rho) : 0.0);
  double k = static_cast<double>(m.x.cols() + (m.ar ? 1 : 0));
  for (const Term& t : m.terms) k += t.scanned > 0 ? 1.0 : 0.0;  // tau or change point
  return -2.0 * loglik + k * std::log(n);
}

Model without_term(const Model& m, std::size_t i) {
  Model out = m;
  const Term& t = m.terms[i];
  if (t.name == "autocorrelation") {
    out.ar = false;
    out.rho = RhoFit{};
  } else {
    const Index q = t.cols.cols(), first = t.first, p = m.x.cols();
    MatrixXd x(m.x.rows(), p - q);
    x << m.x.leftCols(first), m.x.rightCols(p - first - q);
    out.x = x;
    for (Term& o : out.terms) {
      if (o.name != "autocorrelation" && o.first > first) o.first -= q;
    }
  }
  out.terms.erase(out.terms.begin() + static_cast<std::ptrdiff_t>(i));
  return out;
}

UnbalanceEstimate estimate_of(const Model& m, const ModelData& d) {
  const LinearFit f = fit_linear(m.x, d, m.ar, m.rho.rho);
  UnbalanceEstimate e;
  if (!f.ok) return e;
  // (a, c, K) and their covariance; with a K_T drift referred to the first measurement,
  // where K_T is the calibrated (cold) one: (a, c, K) (1 + kappa t_start), delta method.
  Eigen::Vector3d v = f.beta.head<3>();
  Eigen::Matrix3d cov = f.cov.block<3, 3>(0, 0);
  const auto kt = std::find_if(m.terms.begin(), m.terms.end(), [](const Term& t) { return t.name == "kt_drift"; });
  if (kt != m.terms.end()) {
    const Index j = kt->first;
    const double s = 1.0 + f.beta(j) * d.t_start;
    Eigen::Matrix<double, 3, 4> jac = Eigen::Matrix<double, 3, 4>::Zero();
    jac.leftCols<3>() = s * Eigen::Matrix3d::Identity();
    jac.col(3) = v * d.t_start;
    Eigen::Matrix4d c4;
    const std::array<Index, 4> idx{0, 1, 2, j};
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) c4(r, c) = f.cov(idx[r], idx[c]);
    }
    cov = jac * c4 * jac.transpose();
    v *= s;
  }
  const double a = v(0), c = v(1);
  e.amplitude = std::hypot(a, c);
  e.phase = wrap_two_pi(std::atan2(c, a));
  e.offset = v(2);
  const Eigen::Matrix2d cov2 = cov.block<2, 2>(0, 0);
  if (e.amplitude > 0.0) {
    const Eigen::Vector2d ua(a / e.amplitude, c / e.amplitude), up(-ua(1), ua(0));
    e.se_amplitude = std::sqrt(std::max(0.0, ua.dot(cov2 * ua)));
    e.se_phase = std::sqrt(std::max(0.0, up.dot(cov2 * up))) / e.amplitude;
  } else {
    e.se_amplitude = std::sqrt(0.5 * (cov2(0, 0) + cov2(1, 1)));
    e.se_phase = std::numeric_limits<double>::infinity();
  }
  e.se_offset = std::sqrt(std::max(0.0, cov(2, 2)));
  return e;
}

Model with_term(const Model& m, const ModelData& d, Term t) {
  Model out = m;
  if (t.name == "autocorrelation") {
    out.ar = true;
  } else {
    t.first = out.x.cols();
    out.x = with_columns(out.x, t.cols);
  }
  out.terms.push_back(std::move(t));
  if (out.ar) out.rho = fit_rho(out.x, d);
  return out;
}

}  // namespace poise::estimators::detail
