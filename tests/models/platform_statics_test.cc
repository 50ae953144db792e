// Three-gimbal platform statics (Yang 2015 Eqs. 1-12): hand-computed cases, the printed
// expansions against the rotation matrices, the balance conditions, the LOS error and the
// stabilization loop.
#include "models/platform_statics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "models/stabilization_loop.h"

namespace poise::models {
namespace {

constexpr double kG = 9.80665;
constexpr double kDeg = std::numbers::pi / 180.0;
const Eigen::Vector3d kGravity(0.0, 0.0, -kG);

Platform one_mass(Axis a, double m, const Eigen::Vector3d& r) {
  Platform p;
  p.body(a).add_point_mass(m, r);
  return p;
}

TEST(PlatformStatics, InnerOffsetMassUnderGravityByHand) {
  // 0.5 kg, 2 mm along z_p. At gamma = 0 gravity is along the offset: no torque. At
  // gamma = 90 deg the offset lies along +x_b, horizontal: torque m g z about +y.
  const Platform p = one_mass(Axis::kInner, 0.5, {0, 0, 2e-3});
  EXPECT_NEAR(unbalance_torques(p, {}, kGravity).axis[0], 0.0, 1e-15);
  const PlatformTorques t = unbalance_torques(p, {0, 0, 90 * kDeg}, kGravity);
  EXPECT_NEAR(t.axis[0], 0.5 * kG * 2e-3, 1e-12);
  EXPECT_NEAR(t.paper(Axis::kInner).y(), -0.5 * kG * 2e-3, 1e-12);
  // The inner mass hangs on the middle and outer axes too: at gamma = 90 deg its weight
  // acts at x_m = 2 mm, about z_m (beta = 0, alpha = 0: gravity along -z_m) no torque,
  // about x_o none either (the offset is along x).
  EXPECT_NEAR(t.axis[1], 0.0, 1e-15);
  EXPECT_NEAR(t.axis[2], 0.0, 1e-15);
}

TEST(PlatformStatics, InnerAxialOffsetLoadsTheMiddleAxis) {
  // Eq. 9: y_p is invisible to the inner axis but loads the middle one. 0.4 kg at
  // y_p = 1.5 mm, alpha = beta = 90 deg: gravity along -x_m, torque m g y about +z_m.
  const Platform p = one_mass(Axis::kInner, 0.4, {0, 1.5e-3, 0});
  const PlatformTorques t = unbalance_torques(p, {90 * kDeg, 90 * kDeg, 0.0}, kGravity);
  EXPECT_NEAR(t.axis[0], 0.0, 1e-15);
  EXPECT_NEAR(t.axis[1], 0.4 * kG * 1.5e-3, 1e-12);
}

TEST(PlatformStatics, MiddleAxialOffsetLoadsTheOuterAxis) {
  // Eq. 12: z_m loads only the outer axis. 0.6 kg at z_m = 1 mm, alpha = 90 deg.
  const Platform p = one_mass(Axis::kMiddle, 0.6, {0, 0, 1e-3});
  const PlatformTorques t = unbalance_torques(p, {90 * kDeg, 30 * kDeg, 20 * kDeg}, kGravity);
  EXPECT_NEAR(t.axis[1], 0.0, 1e-15);
  EXPECT_NEAR(t.axis[2], 0.6 * kG * 1e-3, 1e-12);
}

TEST(PlatformStatics, CarrierAccelerationOnlyByHand) {
  // No gravity, carrier accelerating at 50 m/s^2 along +x_b: the inertial force -m a acts
  // at the centroid. 0.5 kg at z_p = 2 mm, all angles zero: torque (z e_z) x (-m a e_x)
  // = -m a z e_y on the inner axis.
  const Platform p = one_mass(Axis::kInner, 0.5, {0, 0, 2e-3});
  const Eigen::Vector3d f = -Eigen::Vector3d(50.0, 0, 0);
  EXPECT_NEAR(unbalance_torques(p, {}, f).axis[0], -0.5 * 50.0 * 2e-3, 1e-12);
  // The sensitivities c_k give the same torque as c_k . f.
  const auto c = torque_sensitivities(p, {});
  EXPECT_NEAR(c[0].dot(f), -0.5 * 50.0 * 2e-3, 1e-12);
}

TEST(PlatformStatics, PrintedEquationsAgainstRotationMatrices) {
  std::mt19937_64 rng(2015);
  std::uniform_real_distribution<double> ang(-std::numbers::pi, std::numbers::pi), off(-2e-3, 2e-3);
  for (int trial = 0; trial < 200; ++trial) {
    const GimbalAngles q{ang(rng), ang(rng), ang(rng)};
    PrintedInputs in;
    in.m_p = 0.4;
    in.m_m = 0.7;
    in.m_o = 1.1;
    in.r_p = {off(rng), off(rng), off(rng)};
    in.r_m = {off(rng), off(rng), off(rng)};
    in.r_o = {off(rng), off(rng), off(rng)};
    Platform p;
    p.inner.add_point_mass(in.m_p, in.r_p);
    p.middle.add_point_mass(in.m_m, in.r_m);
    p.outer.add_point_mass(in.m_o, in.r_o);
    const FrameForces f = specific_force_in_frames(q, kGravity);
    EXPECT_LT((f.outer - printed_eq1(q, kG)).norm(), 1e-12);
    EXPECT_LT((f.middle - printed_eq2(q, kG)).norm(), 1e-12);
    EXPECT_LT((f.inner - printed_eq3(q, kG)).norm(), 1e-12);
    const PlatformTorques t = unbalance_torques(p, q, kGravity);
    // The paper's M = m [g~] r is minus the gravity torque.
    EXPECT_LT((t.paper(Axis::kInner) - printed_eq4(q, in)).norm(), 1e-14);
    EXPECT_LT((t.paper(Axis::kOuter) - printed_eq10(q, in)).norm(), 1e-14);
    const Eigen::Vector3d m7 = t.paper(Axis::kMiddle), p7 = printed_eq7(q, in);
    EXPECT_NEAR(m7.x(), p7.x(), 1e-14);
    EXPECT_NEAR(m7.z(), p7.z(), 1e-14);
    // Eq. 7's M_my as printed (OCR 001) has y_p where x_p belongs: off by exactly
    // -m_p g (x_p - y_p) sin a sin b sin c.
    const double slip = -in.m_p * kG * (in.r_p.x() - in.r_p.y()) * std::sin(q.alpha) * std::sin(q.beta) * std::sin(q.gamma);
    EXPECT_NEAR(m7.y() - p7.y(), slip, 1e-14);
    if (std::abs(slip) > 1e-6) {
      EXPECT_GT(std::abs(m7.y() - p7.y()), 1e-7);
    }
  }
}

TEST(PlatformStatics, BalanceConditionsOfEq12HoldAtEveryAngleAndAcceleration) {
  // Eq. 12: x_p = z_p = 0, x_m = 0, y_o = 0, m_m y_m + m_p y_p = 0, m_o z_o + m_m z_m = 0.
  // Free: y_p, z_m, x_o (along their own axes) and the compensating y_m, z_o.
  Platform p;
  p.inner.add_point_mass(0.4, {0, 1.2e-3, 0});
  p.middle.add_point_mass(0.6, {0, -0.4 * 1.2e-3 / 0.6, 0.8e-3});
  p.outer.add_point_mass(1.0, {0.5e-3, 0, -0.6 * 0.8e-3 / 1.0});
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> ang(-std::numbers::pi, std::numbers::pi), acc(-100, 100);
  for (int trial = 0; trial < 100; ++trial) {
    const GimbalAngles q{ang(rng), ang(rng), ang(rng)};
    const Eigen::Vector3d f = kGravity - Eigen::Vector3d(acc(rng), acc(rng), acc(rng));
    const PlatformTorques t = unbalance_torques(p, q, f);
    for (double v : t.axis) EXPECT_NEAR(v, 0.0, 1e-15);
  }
  // Break m_o z_o + m_m z_m = 0 and the outer axis feels it at alpha = 90 deg.
  p.outer.add_point_mass(0.01, {0, 0, 1e-3});
  EXPECT_NEAR(unbalance_torques(p, {90 * kDeg, 0, 0}, kGravity).axis[2], 0.01 * kG * 1e-3, 1e-12);
}

TEST(PlatformStatics, OutboardAssemblyAndCounterweightInertia) {
  Platform p;
  p.inner.mass = 0.4;
  p.inner.inertia = Eigen::Vector3d(1e-4, 2e-4, 3e-4).asDiagonal();
  p.middle.mass = 0.6;
  p.middle.inertia = Eigen::Vector3d(4e-4, 5e-4, 6e-4).asDiagonal();
  // Middle axis z, inner turned 90 deg about y: the inner's z (3e-4) lies along -x_m and its
  // x (1e-4) along z_m.
  const GimbalBody a = outboard_assembly(p, Axis::kMiddle, {0, 0, 90 * kDeg});
  EXPECT_NEAR(a.mass, 1.0, 1e-15);
  EXPECT_NEAR(a.inertia(2, 2), 6e-4 + 1e-4, 1e-15);
  EXPECT_NEAR(a.inertia(0, 0), 4e-4 + 3e-4, 1e-15);
  // A 10 g counterweight at 30 mm from z adds m r^2 about z.
  p.middle.add_point_mass(0.01, {0.03, 0, 0.005});
  EXPECT_NEAR(outboard_assembly(p, Axis::kMiddle, {}).inertia(2, 2), 6e-4 + 3e-4 + 0.01 * 0.03 * 0.03, 1e-15);
}

TEST(PlatformStatics, LosErrorFromAxisErrors) {
  // At zero angles the LOS is x_b: an outer (roll about x) error does not move it; middle
  // (about z) and inner (about y) errors move it by themselves.
  EXPECT_NEAR(los_error_from_axis_errors({}, 1e-4, 0, 0), 0.0, 1e-18);
  EXPECT_NEAR(los_error_from_axis_errors({}, 0, 2e-5, 0), 2e-5, 1e-18);
  EXPECT_NEAR(los_error_from_axis_errors({}, 0, 0, 3e-5), 3e-5, 1e-18);
  // Inner at 90 deg: the LOS points along -z_m, the middle axis, so a middle error does not
  // move it and an outer one does.
  const GimbalAngles q{0, 0, 90 * kDeg};
  EXPECT_NEAR(line_of_sight(q).z(), -1.0, 1e-15);
  EXPECT_NEAR(los_error_from_axis_errors(q, 0, 2e-5, 0), 0.0, 1e-18);
  EXPECT_NEAR(los_error_from_axis_errors(q, 2e-5, 0, 0), 2e-5, 1e-18);
}

TEST(CarrierProfile, RampAndVibration) {
  CarrierProfile p;
  p.duration = 1.0;
  p.time_step = 1e-3;
  p.manoeuvre = {0, 30, 0};
  p.onset = 0.2;
  p.rise_time = 0.1;
  p.vibration.push_back({{0, 0, 5}, 100.0});
  EXPECT_EQ(p.steps(), 1001u);
  EXPECT_NEAR(p.acceleration(0.1).y(), 0.0, 1e-15);
  EXPECT_NEAR(p.acceleration(0.25).y(), 15.0, 1e-12);
  EXPECT_NEAR(p.acceleration(0.5).y(), 30.0, 1e-12);
  EXPECT_NEAR(p.acceleration(0.0025).z(), 5.0, 1e-9);
}

}  // namespace
}  // namespace poise::models
