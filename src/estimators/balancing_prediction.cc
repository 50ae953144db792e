#include "estimators/balancing_prediction.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include <Eigen/Dense>
#include <boost/math/distributions/fisher_f.hpp>

namespace poise::estimators {
namespace {

using CMatrix = Eigen::Matrix<Phasor, Eigen::Dynamic, Eigen::Dynamic>;
using CVector = Eigen::Matrix<Phasor, Eigen::Dynamic, 1>;
using RMatrix = Eigen::MatrixXd;

// The degrees of freedom of a known variance (F(2, nu) is then chi-square's, to 1e-9).
constexpr double kKnownVariance = 1e12;

// Answers as functions of the coefficients (a row [a_s, h_s1 ..] per sensor) and a run's mean
// readings.
using Answers = std::function<CVector(const CMatrix& beta, const CVector& v)>;

CMatrix coefficients(const InfluenceCalibration& c) {
  CMatrix beta(static_cast<Eigen::Index>(c.sensors), static_cast<Eigen::Index>(c.planes + 1));
  for (std::size_t s = 0; s < c.sensors; ++s) {
    const auto row = static_cast<Eigen::Index>(s);
    beta(row, 0) = c.initial[s].value;
    for (std::size_t p = 0; p < c.planes; ++p) beta(row, static_cast<Eigen::Index>(p) + 1) = c.h[s][p].value;
  }
  return beta;
}

CMatrix design_inverse(const InfluenceCalibration& c) {
  const auto k = static_cast<Eigen::Index>(c.planes + 1);
  CMatrix m(k, k);
  for (Eigen::Index i = 0; i < k; ++i) {
    for (Eigen::Index j = 0; j < k; ++j) m(i, j) = c.design_inverse[static_cast<std::size_t>(i * k + j)];
  }
  return m;
}

// The masses that explain readings d (least squares over the sensors) given coefficients beta.
CVector masses_explaining(const CMatrix& beta, const CVector& d) {
  const CMatrix h = beta.rightCols(beta.cols() - 1);
  return h.colPivHouseholderQr().solve(d);
}

// The real covariance of (Re z_0 .. Re z_n, Im z_0 .. Im z_n) for circular complex errors of
// complex covariance m (E z z^H).
RMatrix real_covariance(const CMatrix& m) {
  const Eigen::Index n = m.rows();
  RMatrix k(2 * n, 2 * n);
  k.topLeftCorner(n, n) = m.real() / 2.0;
  k.bottomRightCorner(n, n) = m.real() / 2.0;
  k.topRightCorner(n, n) = -m.imag() / 2.0;
  k.bottomLeftCorner(n, n) = m.imag() / 2.0;
  return k;
}

// Each answer of f with its region: first-order propagation, sensor by sensor (see the header).
// readings_n = 0: f does not read v.
std::vector<PhasorInterval> propagate(const InfluenceCalibration& c, const CVector& v, double readings_n,
                                      const Answers& f) {
  const CMatrix beta = coefficients(c);
  const CVector y0 = f(beta, v);
  const auto answers = static_cast<std::size_t>(y0.size());
  std::vector<PhasorInterval> out(answers);
  for (std::size_t k = 0; k < answers; ++k) out[k].value = y0(static_cast<Eigen::Index>(k));
  if (c.noise_var.empty()) return out;
  const Eigen::Index nb = beta.cols(), np = nb + (readings_n > 0.0 ? 1 : 0);
  RMatrix template_cov = RMatrix::Zero(2 * np, 2 * np);  // per unit noise variance
  const RMatrix kb = real_covariance(design_inverse(c));
  template_cov.topLeftCorner(nb, nb) = kb.topLeftCorner(nb, nb);
  template_cov.block(np, np, nb, nb) = kb.bottomRightCorner(nb, nb);
  template_cov.block(0, np, nb, nb) = kb.topRightCorner(nb, nb);
  template_cov.block(np, 0, nb, nb) = kb.bottomLeftCorner(nb, nb);
  if (readings_n > 0.0) {
    template_cov(nb, nb) = 0.5 / readings_n;
    template_cov(np + nb, np + nb) = 0.5 / readings_n;
  }
  // A declared noise is a known variance: as good as infinitely many degrees of freedom.
  const double nu_sensor = c.noise_declared ? kKnownVariance : 2.0 * static_cast<double>(c.dof);
  std::vector<RMatrix> cov(answers, RMatrix::Zero(2, 2));
  std::vector<std::vector<RMatrix>> parts(answers);  // per answer, each sensor's share
  for (std::size_t s = 0; s < c.sensors; ++s) {
    const auto row = static_cast<Eigen::Index>(s);
    const double scale = std::max(beta.row(row).cwiseAbs().maxCoeff(), std::abs(v.size() ? v(row) : Phasor(0.0)));
    RMatrix jac(2 * static_cast<Eigen::Index>(answers), 2 * np);
    for (Eigen::Index j = 0; j < np; ++j) {
      for (int part = 0; part < 2; ++part) {
        const Phasor step = part == 0 ? Phasor(1e-6 * scale, 0.0) : Phasor(0.0, 1e-6 * scale);
        CMatrix bp = beta, bm = beta;
        CVector vp = v, vm = v;
        if (j < nb) {
          bp(row, j) += step;
          bm(row, j) -= step;
        } else {
          vp(row) += step;
          vm(row) -= step;
        }
        const CVector dy = (f(bp, vp) - f(bm, vm)) / (2e-6 * scale);
        const Eigen::Index col = j + part * np;
        for (std::size_t k = 0; k < answers; ++k) {
          jac(2 * static_cast<Eigen::Index>(k), col) = dy(static_cast<Eigen::Index>(k)).real();
          jac(2 * static_cast<Eigen::Index>(k) + 1, col) = dy(static_cast<Eigen::Index>(k)).imag();
        }
      }
    }
    const RMatrix a = jac * template_cov * jac.transpose();
    for (std::size_t k = 0; k < answers; ++k) {
      const RMatrix block =
          c.noise_var[s] * a.block(2 * static_cast<Eigen::Index>(k), 2 * static_cast<Eigen::Index>(k), 2, 2);
      cov[k] += block;
      parts[k].push_back(block);
    }
  }
  for (std::size_t k = 0; k < answers; ++k) {
    out[k].covariance = std::array<double, 3>{cov[k](0, 0), cov[k](0, 1), cov[k](1, 1)};
    // Welch-Satterthwaite along each principal axis of the covariance; the smaller (a direction
    // that one sensor dominates has that sensor's few degrees of freedom).
    const Eigen::SelfAdjointEigenSolver<RMatrix> axes(cov[k]);
    double dof = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 2; ++axis) {
      const Eigen::Vector2d e = axes.eigenvectors().col(axis);
      double sum = 0.0, sq = 0.0;
      for (const RMatrix& b : parts[k]) {
        const double share = e.dot(b * e);
        sum += share;
        sq += share * share / nu_sensor;
      }
      if (sq > 0.0) dof = std::min(dof, sum * sum / sq);
    }
    out[k].dof = std::isfinite(dof) ? dof : nu_sensor;
  }
  return out;
}

// Per-plane answers u, and for two planes static and couple (in mass times radius where every
// radius is known).
CVector with_static_and_couple(const CVector& u, const std::vector<double>& radii) {
  if (u.size() != 2) return u;
  const bool all = std::all_of(radii.begin(), radii.end(), [](double r) { return r > 0.0; });
  const Phasor u1 = u(0) * (all ? radii[0] : 1.0), u2 = u(1) * (all ? radii[1] : 1.0);
  CVector out(4);
  out << u(0), u(1), u1 + u2, (u1 - u2) / 2.0;
  return out;
}

PlaneAnswers plane_answers(std::vector<PhasorInterval> all, std::size_t planes) {
  PlaneAnswers out;
  out.planes.assign(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(planes));
  if (all.size() == planes + 2) {
    out.static_unbalance = all[planes];
    out.couple_unbalance = all[planes + 1];
  }
  return out;
}

}  // namespace

std::optional<double> PhasorInterval::radius() const {
  if (!covariance) return std::nullopt;
  const auto& [xx, xy, yy] = *covariance;
  const double lambda = (xx + yy) / 2.0 + std::hypot((xx - yy) / 2.0, xy);
  const double f = boost::math::quantile(boost::math::fisher_f(2.0, dof), level);
  return std::sqrt(2.0 * f * std::max(lambda, 0.0));
}

bool PhasorInterval::contains(const Phasor& z) const {
  if (!covariance) return false;
  const auto& [xx, xy, yy] = *covariance;
  const double det = xx * yy - xy * xy;
  if (!(det > 0.0)) return false;
  const double dx = z.real() - value.real(), dy = z.imag() - value.imag();
  const double d2 = (yy * dx * dx - 2.0 * xy * dx * dy + xx * dy * dy) / det;
  return d2 <= 2.0 * boost::math::quantile(boost::math::fisher_f(2.0, dof), level);
}

PlaneAnswers unbalance_answers(const InfluenceCalibration& c, const std::vector<std::vector<Phasor>>& readings,
                               const std::vector<double>& radii) {
  CVector mean = CVector::Zero(static_cast<Eigen::Index>(c.sensors));
  for (const auto& r : readings) {
    for (std::size_t s = 0; s < c.sensors; ++s) mean(static_cast<Eigen::Index>(s)) += r[s];
  }
  mean /= static_cast<double>(readings.size());
  const auto f = [&radii](const CMatrix& beta, const CVector& v) {
    return with_static_and_couple(masses_explaining(beta, v - beta.col(0)), radii);
  };
  return plane_answers(propagate(c, mean, static_cast<double>(readings.size()), f), c.planes);
}

PlaneAnswers initial_unbalance_answers(const InfluenceCalibration& c, const std::vector<double>& radii) {
  const auto f = [&radii](const CMatrix& beta, const CVector&) {
    return with_static_and_couple(masses_explaining(beta, beta.col(0)), radii);
  };
  return plane_answers(propagate(c, CVector(), 0.0, f), c.planes);
}

PlaneAnswers correction_answers(const InfluenceCalibration& c, const std::vector<double>& radii) {
  const auto f = [&radii](const CMatrix& beta, const CVector&) {
    return with_static_and_couple(CVector(-masses_explaining(beta, beta.col(0))), radii);
  };
  return plane_answers(propagate(c, CVector(), 0.0, f), c.planes);
}

std::vector<PhasorInterval> residual_reading_answers(const InfluenceCalibration& c) {
  const CMatrix beta = coefficients(c);
  const CVector w = -masses_explaining(beta, beta.col(0));
  CVector x(beta.cols());
  x << 1.0, w;
  const CVector rest = beta * x;
  // The correction w is what is added: the prediction's error is the coefficients' at x plus
  // the new reading's noise, per sensor.
  const double q = (x.transpose() * design_inverse(c) * x.conjugate())(0, 0).real();
  std::vector<PhasorInterval> out(c.sensors);
  for (std::size_t s = 0; s < c.sensors; ++s) {
    out[s].value = rest(static_cast<Eigen::Index>(s));
    if (c.noise_var.empty()) continue;
    const double half = c.noise_var[s] * (1.0 + q) / 2.0;
    out[s].covariance = std::array<double, 3>{half, 0.0, half};
    out[s].dof = c.noise_declared ? kKnownVariance : 2.0 * static_cast<double>(c.dof);
  }
  return out;
}

}  // namespace poise::estimators
