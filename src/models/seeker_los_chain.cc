#include "models/seeker_los_chain.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace poise::models {
namespace {

// asin and atan of arguments that are almost always tiny (pointing errors ~1e-4 rad):
// the series is exact to double precision below 1e-3 (next term < 1e-16 relative).
constexpr double kSeriesLimit = 1e-3;
inline double asin_series(double x) {
  const double x2 = x * x;
  return x * (1.0 + x2 * (1.0 / 6.0 + x2 * (3.0 / 40.0)));
}
inline double atan_series(double x) {
  const double x2 = x * x;
  return x * (1.0 - x2 * (1.0 / 3.0 - x2 * (1.0 / 5.0)));
}
inline double small_asin(double x) { return std::abs(x) < kSeriesLimit ? asin_series(x) : std::asin(x); }
inline double small_atan(double x) { return std::abs(x) < kSeriesLimit ? atan_series(x) : std::atan(x); }

// T(a -> u) w for unit a, u: with v = a x u, c = a . u, [v]x^2 = v v^T - |v|^2 I and
// |v|^2 = 1 - c^2, I + [v]x + [v]x^2 / (1 + c) applied to w is c w + v x w + v (v . w) / (1 + c).
inline Eigen::Vector3d apply_tilt(const Eigen::Vector3d& a, const Eigen::Vector3d& u, const Eigen::Vector3d& w) {
  const Eigen::Vector3d v = a.cross(u);
  const double c = a.dot(u);
  return c * w + v.cross(w) + v * (v.dot(w) / (1.0 + c));
}

// T(a -> u) for u = normalize(a + t1 e1 + t2 e2).
inline Eigen::Matrix3d tilt_rotation(const Eigen::Vector3d& a, const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
                                     const Eigen::Vector2d& t) {
  const Eigen::Vector3d u = (a + t[0] * e1 + t[1] * e2).normalized();
  return minimal_rotation(a, u);
}

// Error of unit LOS d against the nominal LOS with precomputed cos/sin of alpha, beta.
inline PointingError error_against(const Eigen::Vector3d& d, double ca, double sa, double cb, double sb) {
  const Eigen::Vector3d n(cb * ca, cb * sa, sb);
  PointingError e;
  e.total = 2.0 * small_asin(0.5 * (d - n).norm());
  // Yaw: angle of d's horizontal projection from azimuth alpha.
  const double along = d.x() * ca + d.y() * sa;
  const double across = -d.x() * sa + d.y() * ca;
  e.yaw = along > 0 ? small_atan(across / along) : std::atan2(across, along);
  // Pitch: sin(beta' - beta) = d.z cos b - rho sin b, rho = |horizontal projection|.
  const double rho = std::sqrt(d.x() * d.x() + d.y() * d.y());
  e.pitch = small_asin(d.z() * cb - rho * sb);
  return e;
}

// One yaw angle's row of errors over beta, branch-free so that it vectorizes: the series of
// small_asin and small_atan everywhere, their arguments kept for the caller, which redoes the
// row by error_against if any point is outside their range (errors above ~200 arcsec or a LOS
// behind the yaw azimuth: never in a tolerance study, kept exact anyway). restrict: the
// arrays are disjoint, so no run-time alias checks. Cloned for AVX2 (4 doubles a lane, picked
// at run time; no FMA, so every result is bit-identical to the SSE2 clone's). Not under
// ThreadSanitizer: the clones' resolver (an ifunc) runs while the dynamic loader relocates, before
// TSan's runtime is up, and its instrumented code crashes the process then (the kinds' tests
// segfaulted at start); the SSE2 code alone gives the same results.
#if defined(__SANITIZE_THREAD__)
#define POISE_ERROR_ROW_CLONES
#else
#define POISE_ERROR_ROW_CLONES __attribute__((target_clones("avx2", "default")))
#endif
POISE_ERROR_ROW_CLONES void error_row(const Eigen::Matrix3d& m, double ca, double sa, std::size_t nb,
                                      const double* __restrict qx, const double* __restrict qy,
                                      const double* __restrict qz, const double* __restrict cb,
                                      const double* __restrict sb, double* __restrict tot, double* __restrict yaw,
                                      double* __restrict pit, double* __restrict arg_h, double* __restrict arg_r,
                                      double* __restrict arg_p, double* __restrict arg_a) {
  const double m00 = m(0, 0), m01 = m(0, 1), m02 = m(0, 2), m10 = m(1, 0), m11 = m(1, 1), m12 = m(1, 2), m20 = m(2, 0),
               m21 = m(2, 1), m22 = m(2, 2);
  for (std::size_t ib = 0; ib < nb; ++ib) {
    const double dx = m00 * qx[ib] + m01 * qy[ib] + m02 * qz[ib];
    const double dy = m10 * qx[ib] + m11 * qy[ib] + m12 * qz[ib];
    const double dz = m20 * qx[ib] + m21 * qy[ib] + m22 * qz[ib];
    const double ex = dx - cb[ib] * ca, ey = dy - cb[ib] * sa, ez = dz - sb[ib];
    const double h = 0.5 * std::sqrt(ex * ex + ey * ey + ez * ez);
    const double along = dx * ca + dy * sa;
    const double across = -dx * sa + dy * ca;
    const double r = across / along;
    const double sp = dz * cb[ib] - std::sqrt(dx * dx + dy * dy) * sb[ib];
    tot[ib] = 2.0 * asin_series(h);
    yaw[ib] = atan_series(r);
    pit[ib] = asin_series(sp);
    arg_h[ib] = h, arg_r[ib] = r, arg_p[ib] = sp, arg_a[ib] = along;
  }
}

const Eigen::Vector3d kX = Eigen::Vector3d::UnitX();
const Eigen::Vector3d kY = Eigen::Vector3d::UnitY();
const Eigen::Vector3d kZ = Eigen::Vector3d::UnitZ();

}  // namespace

void AxisErrorState::add(const TiltHarmonic& h) {
  // Called for every harmonic of every sample: the message is built only on error.
  if (n_harmonics >= kMaxHarmonics) {
    throw Error("too many tilt harmonics on one axis (max " + std::to_string(kMaxHarmonics) + ")");
  }
  harmonics[static_cast<std::size_t>(n_harmonics++)] = h;
}

Eigen::Vector2d AxisErrorState::tilt(double phi) const {
  Eigen::Vector2d t(static_tilt[0], static_tilt[1]);
  for (int k = 0; k < n_harmonics; ++k) {
    const TiltHarmonic& h = harmonics[static_cast<std::size_t>(k)];
    const double arg = h.order * phi + h.phase;
    t[0] += h.amplitude * std::cos(arg);
    t[1] += h.amplitude * std::sin(arg);
  }
  return t;
}

Eigen::Matrix3d minimal_rotation(const Eigen::Vector3d& a, const Eigen::Vector3d& u) {
  const Eigen::Vector3d v = a.cross(u);
  const double c = a.dot(u);
  Eigen::Matrix3d vx;
  vx << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return Eigen::Matrix3d::Identity() + vx + vx * vx / (1.0 + c);
}

Eigen::Matrix3d yaw_orientation(const AxisErrorState& yaw, double alpha) {
  const double c = std::cos(alpha), s = std::sin(alpha);
  Eigen::Matrix3d rz;
  rz << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  return tilt_rotation(kZ, kX, kY, yaw.tilt(alpha)) * rz;
}

Eigen::Matrix3d pitch_orientation(const AxisErrorState& pitch, double beta) {
  // Rotation by beta about -y: x -> (cos b, 0, sin b).
  const double c = std::cos(beta), s = std::sin(beta);
  Eigen::Matrix3d r;
  r << c, 0.0, -s, 0.0, 1.0, 0.0, s, 0.0, c;
  return tilt_rotation(-kY, kX, kZ, pitch.tilt(beta)) * r;
}

Eigen::Vector3d optical_axis(double collimation) { return Eigen::Vector3d(1.0, collimation, 0.0).normalized(); }

Eigen::Vector3d nominal_los(double alpha, double beta) {
  return {std::cos(beta) * std::cos(alpha), std::cos(beta) * std::sin(alpha), std::sin(beta)};
}

Eigen::Vector3d los_direction(const SeekerErrorState& s, double alpha, double beta) {
  return yaw_orientation(s.yaw, alpha) * (pitch_orientation(s.pitch, beta) * optical_axis(s.collimation));
}

PointingError pointing_error(const Eigen::Vector3d& d, double alpha, double beta) {
  return error_against(d, std::cos(alpha), std::sin(alpha), std::cos(beta), std::sin(beta));
}

std::vector<double> linspace(double lo, double hi, std::size_t n) {
  require(n >= 1, "linspace needs at least one point");
  if (n == 1) return {lo};
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) {
    v[i] = lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(n - 1);
  }
  return v;
}

LosGrid::LosGrid(std::vector<double> alpha, std::vector<double> beta)
    : alpha_(std::move(alpha)), beta_(std::move(beta)) {
  require(!alpha_.empty() && !beta_.empty(), "a LOS grid needs at least one yaw and one pitch angle");
  for (double a : alpha_) {
    ca_.push_back(std::cos(a));
    sa_.push_back(std::sin(a));
  }
  for (double b : beta_) {
    cb_.push_back(std::cos(b));
    sb_.push_back(std::sin(b));
  }
}

LosGrid::Workspace LosGrid::make_workspace() const {
  Workspace ws;
  ws.yaw_frames.resize(alpha_.size());
  ws.pitch_los.resize(beta_.size());
  return ws;
}

void LosGrid::tilts_on_grid(const AxisErrorState& axis, std::span<const double> phi, std::vector<PhaseTable>& tables,
                            std::span<Eigen::Vector2d> out) {
  if (out.size() != phi.size()) throw Error("LOS grid tilt output has the wrong size");
  // Group the harmonics by order: C_n = sum A_h e^{i psi_h} (order 0 is a constant).
  std::array<double, AxisErrorState::kMaxHarmonics> orders{}, cre{}, cim{};
  int groups = 0;
  double s0 = axis.static_tilt[0], s1 = axis.static_tilt[1];
  for (int k = 0; k < axis.n_harmonics; ++k) {
    const TiltHarmonic& h = axis.harmonics[static_cast<std::size_t>(k)];
    const double re = h.amplitude * std::cos(h.phase), im = h.amplitude * std::sin(h.phase);
    if (h.order == 0.0) {
      s0 += re;
      s1 += im;
      continue;
    }
    int g = 0;
    while (g < groups && orders[static_cast<std::size_t>(g)] != h.order) ++g;
    const auto gi = static_cast<std::size_t>(g);
    if (g == groups) {
      orders[gi] = h.order, cre[gi] = 0.0, cim[gi] = 0.0;
      ++groups;
    }
    cre[gi] += re;
    cim[gi] += im;
  }
  for (auto& t : out) t = Eigen::Vector2d(s0, s1);
  for (int g = 0; g < groups; ++g) {
    const auto gi = static_cast<std::size_t>(g);
    const PhaseTable* table = nullptr;
    for (const PhaseTable& t : tables) {
      if (t.order == orders[gi]) table = &t;
    }
    if (table == nullptr) {  // first sample of this thread with this order
      PhaseTable t{orders[gi], std::vector<double>(phi.size()), std::vector<double>(phi.size())};
      for (std::size_t k = 0; k < phi.size(); ++k) {
        t.c[k] = std::cos(orders[gi] * phi[k]);
        t.s[k] = std::sin(orders[gi] * phi[k]);
      }
      tables.push_back(std::move(t));
      table = &tables.back();
    }
    const double a = cre[gi], b = cim[gi];
    for (std::size_t k = 0; k < phi.size(); ++k) {  // C_n e^{i n phi_k}
      out[k][0] += a * table->c[k] - b * table->s[k];
      out[k][1] += a * table->s[k] + b * table->c[k];
    }
  }
}

void LosGrid::evaluate(const SeekerErrorState& s, Workspace& ws, std::span<PointingError> out) const {
  if (out.size() != size()) throw Error("LOS grid output has the wrong size");
  const std::size_t na = alpha_.size(), nb = beta_.size();
  const Eigen::Vector3d l = optical_axis(s.collimation);
  ws.tilts.resize(std::max(na, nb));
  ws.pitch_xyz.resize(3 * nb);
  ws.row.resize(7 * nb);
  const std::span<Eigen::Vector2d> tb(ws.tilts.data(), nb);
  tilts_on_grid(s.pitch, beta_, ws.pitch_phases, tb);
  double* px = ws.pitch_xyz.data();
  double* py = px + nb;
  double* pz = py + nb;
  for (std::size_t ib = 0; ib < nb; ++ib) {
    // O2(beta) l = T(-y -> u) R(-y, beta) l; R(-y, beta) takes x to (cos b, 0, sin b).
    const Eigen::Vector3d rl(cb_[ib] * l.x() - sb_[ib] * l.z(), l.y(), sb_[ib] * l.x() + cb_[ib] * l.z());
    const Eigen::Vector3d p = apply_tilt(-kY, (-kY + tb[ib][0] * kX + tb[ib][1] * kZ).normalized(), rl);
    px[ib] = p.x(), py[ib] = p.y(), pz[ib] = p.z();
    ws.pitch_los[ib] = p;
  }
  const std::span<Eigen::Vector2d> ta(ws.tilts.data(), na);
  tilts_on_grid(s.yaw, alpha_, ws.yaw_phases, ta);
  const double* cb = cb_.data();
  const double* sb = sb_.data();
  const double *qx = px, *qy = py, *qz = pz;
  double* tot = ws.row.data();
  double* yaw = tot + nb;
  double* pit = yaw + nb;
  double* arg_h = pit + nb;  // the series' arguments, checked after the row
  double* arg_r = arg_h + nb;
  double* arg_p = arg_r + nb;
  double* arg_a = arg_p + nb;
  for (std::size_t ia = 0; ia < na; ++ia) {
    // O1(alpha) = T(z -> u) Rz(alpha), column by column.
    const double ca = ca_[ia], sa = sa_[ia];
    const Eigen::Vector3d u = (kZ + ta[ia][0] * kX + ta[ia][1] * kY).normalized();
    Eigen::Matrix3d& m = ws.yaw_frames[ia];
    m.col(0) = apply_tilt(kZ, u, Eigen::Vector3d(ca, sa, 0.0));
    m.col(1) = apply_tilt(kZ, u, Eigen::Vector3d(-sa, ca, 0.0));
    m.col(2) = apply_tilt(kZ, u, kZ);
    error_row(m, ca, sa, nb, qx, qy, qz, cb, sb, tot, yaw, pit, arg_h, arg_r, arg_p, arg_a);
    bool outside = false;
    for (std::size_t ib = 0; ib < nb; ++ib) {
      outside = outside || !(arg_h[ib] < kSeriesLimit && std::abs(arg_r[ib]) < kSeriesLimit &&
                             std::abs(arg_p[ib]) < kSeriesLimit && arg_a[ib] > 0.0);
    }
    PointingError* row_out = out.data() + index(ia, 0);
    if (outside) {
      for (std::size_t ib = 0; ib < nb; ++ib) {
        row_out[ib] = error_against(m * ws.pitch_los[ib], ca, sa, cb[ib], sb[ib]);
      }
      continue;
    }
    for (std::size_t ib = 0; ib < nb; ++ib) row_out[ib] = {tot[ib], yaw[ib], pit[ib]};
  }
}

}  // namespace poise::models
