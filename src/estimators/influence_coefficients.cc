#include "estimators/influence_coefficients.h"

#include <cmath>

#include <Eigen/Dense>

#include "core/error.h"

namespace poise::estimators {
namespace {

using CMatrix = Eigen::Matrix<Phasor, Eigen::Dynamic, Eigen::Dynamic>;
using CVector = Eigen::Matrix<Phasor, Eigen::Dynamic, 1>;

CMatrix influence_matrix(const InfluenceCalibration& c) {
  CMatrix h(static_cast<Eigen::Index>(c.sensors), static_cast<Eigen::Index>(c.planes));
  for (std::size_t s = 0; s < c.sensors; ++s) {
    for (std::size_t p = 0; p < c.planes; ++p) {
      h(static_cast<Eigen::Index>(s), static_cast<Eigen::Index>(p)) = c.h[s][p].value;
    }
  }
  return h;
}

}  // namespace

InfluenceCalibration calibrate(const std::vector<BalancingRun>& runs, std::size_t planes,
                               std::optional<double> declared_sd) {
  std::vector<const BalancingRun*> known;
  for (const auto& r : runs) {
    if (r.masses && !r.check) known.push_back(&r);
  }
  if (known.size() < planes + 1) {
    throw Error("a calibration of " + std::to_string(planes) + " plane(s) needs at least " +
                std::to_string(planes + 1) +
                " runs with known masses (one as the rotor is, one with a trial mass in "
                "each plane); the campaign has " +
                std::to_string(known.size()));
  }
  InfluenceCalibration c;
  c.sensors = known.front()->readings.size();
  c.planes = planes;
  c.runs = known.size();
  c.dof = known.size() - planes - 1;
  const auto n = static_cast<Eigen::Index>(known.size()), k = static_cast<Eigen::Index>(planes + 1);
  CMatrix x(n, k);
  for (Eigen::Index r = 0; r < n; ++r) {
    x(r, 0) = 1.0;
    for (std::size_t p = 0; p < planes; ++p) x(r, static_cast<Eigen::Index>(p) + 1) = (*known[r]->masses)[p];
  }
  const Eigen::ColPivHouseholderQR<CMatrix> qr(x);
  if (qr.rank() < k) {
    throw Error("the runs' masses do not separate the " + std::to_string(planes) +
                " planes (a plane without a trial mass, or two planes always loaded alike): no calibration");
  }
  const CMatrix xhx_inv = (x.adjoint() * x).inverse();
  for (Eigen::Index i = 0; i < k; ++i) {
    for (Eigen::Index j = 0; j < k; ++j) c.design_inverse.push_back(xhx_inv(i, j));
  }
  c.initial.resize(c.sensors);
  c.h.assign(c.sensors, std::vector<PhasorEstimate>(planes));
  c.residuals.assign(known.size(), std::vector<Phasor>(c.sensors));
  for (std::size_t s = 0; s < c.sensors; ++s) {
    CVector y(n);
    for (Eigen::Index r = 0; r < n; ++r) y(r) = known[r]->readings[s];
    const CVector beta = qr.solve(y);
    const CVector e = y - x * beta;
    std::optional<double> s2;
    if (c.dof > 0) {
      s2 = e.squaredNorm() / static_cast<double>(c.dof);
      c.noise_var.push_back(*s2);
    }
    for (Eigen::Index r = 0; r < n; ++r) c.residuals[r][s] = e(r);
    // Each part's sd: the complex variance s^2 (X^H X)^-1_jj is shared by its two parts.
    auto estimate = [&](Eigen::Index j) {
      PhasorEstimate pe{beta(j), std::nullopt};
      if (s2) pe.se = std::sqrt(*s2 * xhx_inv(j, j).real() / 2.0);
      return pe;
    };
    c.initial[s] = estimate(0);
    for (std::size_t p = 0; p < planes; ++p) c.h[s][p] = estimate(static_cast<Eigen::Index>(p) + 1);
  }
  if (c.dof == 0 && declared_sd && *declared_sd > 0.0) {
    c.noise_var.assign(c.sensors, *declared_sd * *declared_sd);
    c.noise_declared = true;
  }
  const Eigen::JacobiSVD<CMatrix> svd(influence_matrix(c));
  const auto& sv = svd.singularValues();
  c.condition = sv(sv.size() - 1) > 0.0 ? sv(0) / sv(sv.size() - 1) : std::numeric_limits<double>::infinity();
  return c;
}

std::vector<Phasor> unbalance_of(const InfluenceCalibration& c, const std::vector<Phasor>& v) {
  const CMatrix h = influence_matrix(c);
  CVector d(static_cast<Eigen::Index>(c.sensors));
  for (std::size_t s = 0; s < c.sensors; ++s) d(static_cast<Eigen::Index>(s)) = v[s] - c.initial[s].value;
  const CVector w = h.colPivHouseholderQr().solve(d);
  return std::vector<Phasor>(w.data(), w.data() + w.size());
}

Correction correction(const InfluenceCalibration& c) {
  const CMatrix h = influence_matrix(c);
  CVector a(static_cast<Eigen::Index>(c.sensors));
  for (std::size_t s = 0; s < c.sensors; ++s) a(static_cast<Eigen::Index>(s)) = c.initial[s].value;
  const CVector w = -h.colPivHouseholderQr().solve(a);
  const CVector rest = a + h * w;
  Correction out;
  out.masses.assign(w.data(), w.data() + w.size());
  out.residual.assign(rest.data(), rest.data() + rest.size());
  out.residual_rms = std::sqrt(rest.squaredNorm() / static_cast<double>(c.sensors));
  return out;
}

}  // namespace poise::estimators
