// Tests of the exact two-axis seeker LOS chain (src/models/seeker_los_chain.h):
// zero-error identity, an independent re-computation with Eigen::AngleAxisd, the
// first-order axis-error formulas, the error definitions, the grid evaluator, the tilt
// harmonics and the minimal rotation.
#include "models/seeker_los_chain.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "core/error.h"

namespace {

using poise::Error;
using poise::models::AxisErrorState;
using poise::models::LosGrid;
using poise::models::PointingError;
using poise::models::SeekerErrorState;
using poise::models::TiltHarmonic;
namespace pm = poise::models;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kArcsec = kPi / (180.0 * 3600.0);

const Eigen::Vector3d kX = Eigen::Vector3d::UnitX();
const Eigen::Vector3d kY = Eigen::Vector3d::UnitY();
const Eigen::Vector3d kZ = Eigen::Vector3d::UnitZ();

// ---- Independent reference implementation (Eigen::AngleAxisd, no code under test). ----

Eigen::Vector2d ref_tilt(const AxisErrorState& s, double phi) {
  Eigen::Vector2d t(s.static_tilt[0], s.static_tilt[1]);
  for (int k = 0; k < s.n_harmonics; ++k) {
    const TiltHarmonic& h = s.harmonics[static_cast<std::size_t>(k)];
    t += h.amplitude * Eigen::Vector2d(std::cos(h.order * phi + h.phase), std::sin(h.order * phi + h.phase));
  }
  return t;
}

// Rotation carrying a onto u = normalize(a + t1 e1 + t2 e2) about the axis a x u.
Eigen::Matrix3d ref_tilt_rotation(const Eigen::Vector3d& a, const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
                                  const Eigen::Vector2d& t) {
  const Eigen::Vector3d u = (a + t[0] * e1 + t[1] * e2).normalized();
  const Eigen::Vector3d axis = a.cross(u);
  const double s = axis.norm();
  if (s == 0.0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(std::atan2(s, a.dot(u)), axis / s).toRotationMatrix();
}

Eigen::Vector3d ref_los(const SeekerErrorState& s, double alpha, double beta) {
  const Eigen::Matrix3d o1 =
      ref_tilt_rotation(kZ, kX, kY, ref_tilt(s.yaw, alpha)) * Eigen::AngleAxisd(alpha, kZ).toRotationMatrix();
  const Eigen::Matrix3d o2 =
      ref_tilt_rotation(-kY, kX, kZ, ref_tilt(s.pitch, beta)) * Eigen::AngleAxisd(beta, -kY).toRotationMatrix();
  return o1 * o2 * Eigen::Vector3d(1.0, s.collimation, 0.0).normalized();
}

Eigen::Vector3d ref_nominal(double alpha, double beta) {
  return {std::cos(beta) * std::cos(alpha), std::cos(beta) * std::sin(alpha), std::sin(beta)};
}

// A random error state with static tilts, bearing-like harmonics and collimation.
SeekerErrorState random_state(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> sym(-1.0, 1.0), ph(0.0, 2.0 * kPi);
  std::uniform_int_distribution<int> order(0, 6), count(0, 5);
  SeekerErrorState s;
  for (AxisErrorState* a : {&s.yaw, &s.pitch}) {
    a->static_tilt = {scale * sym(rng), scale * sym(rng)};
    const int n = count(rng);
    for (int k = 0; k < n; ++k) {
      a->add({0.3 * scale * std::abs(sym(rng)), static_cast<double>(order(rng)), ph(rng)});
    }
  }
  s.collimation = scale * sym(rng);
  return s;
}

std::vector<double> angles(double lo_deg, double hi_deg, double step_deg) {
  std::vector<double> v;
  for (double a = lo_deg; a <= hi_deg + 1e-9; a += step_deg) v.push_back(a * kDeg);
  return v;
}

// ---- (a) zero errors ----

TEST(SeekerLosChain, ZeroErrorsGiveNominalLos) {
  const SeekerErrorState zero;
  for (double a : angles(-180, 180, 7.5)) {
    for (double b : angles(-80, 80, 5)) {
      const Eigen::Vector3d d = pm::los_direction(zero, a, b);
      EXPECT_LT((d - pm::nominal_los(a, b)).norm(), 1e-15) << a << " " << b;
      EXPECT_LT((pm::nominal_los(a, b) - ref_nominal(a, b)).norm(), 1e-16);
      const PointingError e = pm::pointing_error(d, a, b);
      EXPECT_LT(std::abs(e.total), 1e-15);
      EXPECT_LT(std::abs(e.yaw), 1e-15);
      EXPECT_LT(std::abs(e.pitch), 1e-15);
    }
  }
}

// ---- (b) independent recomputation ----

TEST(SeekerLosChain, MatchesIndependentAngleAxisChain) {
  std::mt19937_64 rng(20110611);
  for (double scale : {1e-4, 1e-2, 0.2}) {  // arcsecond-level, then large, to exercise exactness
    for (int trial = 0; trial < 40; ++trial) {
      const SeekerErrorState s = random_state(rng, scale);
      for (double a : angles(-60, 60, 15)) {
        for (double b : angles(-45, 60, 15)) {
          const Eigen::Vector3d d = pm::los_direction(s, a, b);
          const Eigen::Vector3d r = ref_los(s, a, b);
          ASSERT_LT((d - r).norm(), 1e-14) << "scale " << scale << " trial " << trial << " a " << a << " b " << b;
          EXPECT_NEAR(d.norm(), 1.0, 1e-15);
        }
      }
    }
  }
}

TEST(SeekerLosChain, FramesAreRotations) {
  std::mt19937_64 rng(7);
  const SeekerErrorState s = random_state(rng, 1e-3);
  for (double phi : {-1.0, 0.0, 0.3, 2.0}) {
    for (const Eigen::Matrix3d& m : {pm::yaw_orientation(s.yaw, phi), pm::pitch_orientation(s.pitch, phi)}) {
      EXPECT_LT((m.transpose() * m - Eigen::Matrix3d::Identity()).norm(), 1e-15);
      EXPECT_NEAR(m.determinant(), 1.0, 1e-15);
    }
    // Each frame carries its nominal axis onto the tilted axis u(phi).
    const Eigen::Vector2d ty = ref_tilt(s.yaw, phi);
    const Eigen::Vector3d uy = (kZ + ty[0] * kX + ty[1] * kY).normalized();
    EXPECT_LT((pm::yaw_orientation(s.yaw, phi) * kZ - uy).norm(), 1e-15);
    const Eigen::Vector2d tp = ref_tilt(s.pitch, phi);
    const Eigen::Vector3d up = (-kY + tp[0] * kX + tp[1] * kZ).normalized();
    EXPECT_LT((pm::pitch_orientation(s.pitch, phi) * (-kY) - up).norm(), 1e-15);
  }
  EXPECT_LT((pm::optical_axis(0.01) - Eigen::Vector3d(1.0, 0.01, 0.0).normalized()).norm(), 1e-16);
}

// ---- (c) first-order closed forms ----
//
// Derivation from the frames the header defines: T(a -> u) ~ I + [a x u]x, so a yaw-axis tilt
// s = (i cos psi, i sin psi) rotates the nominal LOS n by v = z x u = i (-sin psi, cos psi, 0):
// d ~ n + v x n = n + i (cos psi sin b, sin psi sin b, -cos b cos(a - psi)). Hence
//   pitch = -i cos(a - psi)             (as the header states)
//   yaw   = -i tan(b) sin(a - psi)      (the header states +i tan(b) sin(a - psi))
// A pitch-axis tilt (0, c2) turns the pitch frame about v = (-y) x (c2 z) = -c2 x, so in the
// yaw frame d ~ (cos b, c2 sin b, sin b):
//   yaw   = +c2 tan(b), pitch = 0      (the header states yaw = -c2 tan(b))
// Collimation: l = normalize(1, c3, 0) -> d ~ (cos b, c3, sin b): yaw = c3 / cos(b).
// The tests assert the signs that follow from the frame definitions (and that the code
// implements); the header's first-order signs for yaw disagree (reported).

TEST(SeekerLosChain, FirstOrderYawAxisTilt) {
  const double i = 20.0 * kArcsec;
  const double tol = 1e-3 * i;  // second-order terms are ~ i^2 tan^2 b, 1e-8 rad here
  for (double psi : {0.0, 30 * kDeg, 90 * kDeg, 200 * kDeg, -45 * kDeg}) {
    SeekerErrorState s;
    s.yaw.static_tilt = {i * std::cos(psi), i * std::sin(psi)};
    for (double a : angles(-30, 30, 5)) {
      for (double b : angles(-30, 30, 5)) {
        const PointingError e = pm::pointing_error(pm::los_direction(s, a, b), a, b);
        EXPECT_NEAR(e.yaw, -i * std::tan(b) * std::sin(a - psi), tol) << "psi " << psi << " a " << a << " b " << b;
        EXPECT_NEAR(e.pitch, -i * std::cos(a - psi), tol) << "psi " << psi << " a " << a << " b " << b;
      }
    }
  }
}

TEST(SeekerLosChain, FirstOrderYawTiltSignWorkedExample) {
  // Axis leaning towards +x (psi = 0), looking along +y (a = 90 deg) at b = 30 deg: the tilt
  // is a rotation by +i about +y, which moves the LOS (0, cos b, sin b) to
  // (i sin b, cos b, sin b): its azimuth atan2(y, x) = 90 deg - i tan b, i.e. yaw < 0.
  const double i = 20.0 * kArcsec;
  SeekerErrorState s;
  s.yaw.static_tilt = {i, 0.0};
  const double a = 90 * kDeg, b = 30 * kDeg;
  const Eigen::Vector3d d = pm::los_direction(s, a, b);
  EXPECT_NEAR(d.x(), i * std::sin(b), 1e-12);
  const PointingError e = pm::pointing_error(d, a, b);
  EXPECT_LT(e.yaw, 0.0);
  EXPECT_NEAR(e.yaw, -i * std::tan(b), 1e-3 * i);
}

TEST(SeekerLosChain, FirstOrderPitchPerpendicularity) {
  const double c2 = 20.0 * kArcsec;
  const double tol = 1e-3 * c2;
  SeekerErrorState s;
  s.pitch.static_tilt = {0.0, c2};
  for (double a : angles(-30, 30, 5)) {
    for (double b : angles(-30, 30, 5)) {
      const PointingError e = pm::pointing_error(pm::los_direction(s, a, b), a, b);
      EXPECT_NEAR(e.yaw, c2 * std::tan(b), tol) << "a " << a << " b " << b;
      EXPECT_NEAR(e.pitch, 0.0, tol) << "a " << a << " b " << b;
    }
  }
}

TEST(SeekerLosChain, FirstOrderCollimation) {
  const double c3 = 20.0 * kArcsec;
  const double tol = 1e-3 * c3;
  SeekerErrorState s;
  s.collimation = c3;
  for (double a : angles(-30, 30, 5)) {
    for (double b : angles(-30, 30, 5)) {
      const PointingError e = pm::pointing_error(pm::los_direction(s, a, b), a, b);
      EXPECT_NEAR(e.yaw, c3 / std::cos(b), tol) << "a " << a << " b " << b;
      EXPECT_NEAR(e.pitch, 0.0, tol) << "a " << a << " b " << b;
      // On the sky the LOS moves by about c3 whatever the elevation.
      EXPECT_NEAR(e.total, c3, tol);
    }
  }
}

// ---- (d), plus the yaw / pitch definitions ----

TEST(SeekerLosChain, ErrorDefinitions) {
  std::mt19937_64 rng(99);
  for (double scale : {1e-5, 1e-3, 0.05}) {
    for (int trial = 0; trial < 30; ++trial) {
      const SeekerErrorState s = random_state(rng, scale);
      for (double a : angles(-170, 170, 34)) {
        for (double b : angles(-60, 60, 20)) {
          const Eigen::Vector3d d = pm::los_direction(s, a, b);
          const Eigen::Vector3d n = ref_nominal(a, b);
          const PointingError e = pm::pointing_error(d, a, b);
          EXPECT_NEAR(e.total, std::atan2(d.cross(n).norm(), d.dot(n)), 1e-12);
          // yaw = atan2(d.y, d.x) - alpha (wrapped), pitch = asin(d.z) - beta.
          EXPECT_NEAR(e.yaw, std::remainder(std::atan2(d.y(), d.x()) - a, 2.0 * kPi), 1e-12);
          EXPECT_NEAR(e.pitch, std::asin(d.z()) - b, 1e-12);
          EXPECT_GE(e.total, 0.0);
        }
      }
    }
  }
}

// ---- (e) grid evaluator ----

TEST(SeekerLosChain, GridMatchesPointwiseEvaluation) {
  std::mt19937_64 rng(31);
  const LosGrid grid(pm::linspace(-30 * kDeg, 30 * kDeg, 13), pm::linspace(-20 * kDeg, 40 * kDeg, 9));
  ASSERT_EQ(grid.size(), 13u * 9u);
  LosGrid::Workspace ws = grid.make_workspace();
  std::vector<PointingError> out(grid.size());
  for (int trial = 0; trial < 5; ++trial) {
    SeekerErrorState s = random_state(rng, 1e-4);
    s.yaw.add({2e-5, 1.0, 0.3});
    s.pitch.add({1e-5, 2.0, -1.1});
    grid.evaluate(s, ws, out);
    for (std::size_t ia = 0; ia < grid.alpha().size(); ++ia) {
      for (std::size_t ib = 0; ib < grid.beta().size(); ++ib) {
        const double a = grid.alpha()[ia], b = grid.beta()[ib];
        const PointingError p = pm::pointing_error(pm::los_direction(s, a, b), a, b);
        const PointingError& g = out[grid.index(ia, ib)];
        EXPECT_NEAR(g.total, p.total, 1e-13);
        EXPECT_NEAR(g.yaw, p.yaw, 1e-13);
        EXPECT_NEAR(g.pitch, p.pitch, 1e-13);
      }
    }
  }
  std::vector<PointingError> wrong(3);
  EXPECT_THROW(grid.evaluate(SeekerErrorState{}, ws, wrong), Error);
  EXPECT_THROW(LosGrid({}, {0.0}), Error);
}

TEST(SeekerLosChain, Linspace) {
  const std::vector<double> v = pm::linspace(-30 * kDeg, 30 * kDeg, 61);
  ASSERT_EQ(v.size(), 61u);
  EXPECT_EQ(v.front(), -30 * kDeg);
  EXPECT_EQ(v.back(), 30 * kDeg);
  EXPECT_NEAR(v[30], 0.0, 1e-17);
  EXPECT_NEAR(v[1] - v[0], kDeg, 1e-16);
  EXPECT_EQ(pm::linspace(0.5, 2.0, 1), std::vector<double>{0.5});
  EXPECT_THROW(pm::linspace(0.0, 1.0, 0), Error);
}

// ---- (f) tilt harmonics ----

TEST(SeekerLosChain, TiltHarmonicRotatesWithShaftAngle) {
  AxisErrorState a;
  const double amp = 3e-5, psi = 0.7;
  a.add({amp, 1.0, psi});
  for (double phi : {0.0, 0.5, 1.0, 2.5, -3.0, 6.0}) {
    const Eigen::Vector2d t = a.tilt(phi);
    EXPECT_NEAR(t[0], amp * std::cos(phi + psi), 1e-20);
    EXPECT_NEAR(t[1], amp * std::sin(phi + psi), 1e-20);
    EXPECT_NEAR(t.norm(), amp, 1e-20);  // run-out wobble: constant magnitude, turning direction
  }
  // Static offset plus an order-2 harmonic.
  AxisErrorState b;
  b.static_tilt = {1e-5, -2e-5};
  b.add({4e-6, 2.0, 0.0});
  EXPECT_NEAR(b.tilt(0.25)[0], 1e-5 + 4e-6 * std::cos(0.5), 1e-20);
  EXPECT_NEAR(b.tilt(0.25)[1], -2e-5 + 4e-6 * std::sin(0.5), 1e-20);
  // Order 0 is a static tilt in direction psi.
  AxisErrorState c;
  c.add({5e-6, 0.0, kPi / 2});
  EXPECT_NEAR(c.tilt(1.234)[0], 0.0, 1e-20);
  EXPECT_NEAR(c.tilt(1.234)[1], 5e-6, 1e-20);
}

TEST(SeekerLosChain, TooManyHarmonicsThrow) {
  AxisErrorState a;
  for (int k = 0; k < AxisErrorState::kMaxHarmonics; ++k) a.add({1e-6, 1.0, 0.0});
  EXPECT_EQ(a.n_harmonics, AxisErrorState::kMaxHarmonics);
  EXPECT_THROW(a.add({1e-6, 1.0, 0.0}), Error);
  EXPECT_EQ(a.n_harmonics, AxisErrorState::kMaxHarmonics);
  // All 24 equal harmonics sum.
  EXPECT_NEAR(a.tilt(0.0)[0], 24e-6, 1e-18);
}

TEST(SeekerLosChain, YawHarmonicErrorFollowsShaftAngle) {
  // A once-per-turn yaw-axis wobble of amplitude A and phase psi is, at yaw angle a, a static
  // tilt A towards azimuth a + psi: pitch = -A cos(psi), the same at every a.
  const double amp = 10.0 * kArcsec, psi = 0.4;
  SeekerErrorState s;
  s.yaw.add({amp, 1.0, psi});
  for (double a : angles(-30, 30, 10)) {
    const PointingError e = pm::pointing_error(pm::los_direction(s, a, 0.2), a, 0.2);
    EXPECT_NEAR(e.pitch, -amp * std::cos(psi), 1e-3 * amp);
    EXPECT_NEAR(e.yaw, amp * std::tan(0.2) * std::sin(psi), 1e-3 * amp);
  }
}

// ---- (g) minimal rotation ----

TEST(SeekerLosChain, MinimalRotation) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d from = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    // Targets near and far (but not antiparallel: the formula divides by 1 + from.to).
    const double spread = trial < 100 ? 1e-4 : 1.0;
    const Eigen::Vector3d to = (from + spread * Eigen::Vector3d(g(rng), g(rng), g(rng))).normalized();
    if (from.dot(to) < -0.9) continue;
    const Eigen::Matrix3d r = pm::minimal_rotation(from, to);
    // Rounding grows with the angle (1 / (1 + from.to) up to 10 here): 1e-15 for small turns,
    // 1e-14 for large ones.
    const double tol = trial < 100 ? 1e-15 : 1e-14;
    EXPECT_LT((r * from - to).norm(), tol);
    EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 2.0 * tol);
    EXPECT_NEAR(r.determinant(), 1.0, 2.0 * tol);
    // Minimal: the axis from x to is left fixed and the angle is the angle between them.
    const Eigen::Vector3d axis = from.cross(to);
    if (axis.norm() > 1e-8) {
      EXPECT_LT((r * axis - axis).norm(), tol);
      const Eigen::AngleAxisd aa(r);
      EXPECT_NEAR(aa.angle(), std::atan2(axis.norm(), from.dot(to)), 1e-12);
    }
  }
  EXPECT_EQ(pm::minimal_rotation(kX, kX), Eigen::Matrix3d::Identity());
}

}  // namespace
