// The spring-plate machine's sensors as built (models/spring_plate_machine.h): the torsional
// plate's end condition against an independent solution of the beam equation, and sensor 1
// reading its own horizontal plate.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include <Eigen/Dense>

#include "models/spring_plate_machine.h"

namespace poise::models {
namespace {

// Independent: solve E I w'''' = 0 on [0, L] as w = c0 + c1 x + c2 x^2 + c3 x^3 with the four
// boundary conditions of the end condition (a 4x4 linear system), then the end shear
// F = -E I w'''(L) (force on the plate's end), the end moment M = E I w''(L), and the strain
// energy U = 1/2 int E I w''^2 dx by Simpson's rule. The swing theta moves the end by l theta.
struct BeamSolution {
  double force = 0.0, moment = 0.0, energy = 0.0, max_moment = 0.0;
};
BeamSolution solve_beam(const SpringPlate& p, TorsionPlateEnd end, double lever, double theta) {
  const double ei = p.youngs_modulus * p.width * std::pow(p.thickness, 3) / 12.0, len = p.length;
  Eigen::Matrix4d a = Eigen::Matrix4d::Zero();
  Eigen::Vector4d b = Eigen::Vector4d::Zero();
  a(0, 0) = 1;                                      // w(0) = 0
  a(1, 1) = 1;                                      // w'(0) = 0
  a.row(2) << 1, len, len * len, len * len * len;   // w(L) = l theta
  b(2) = lever * theta;
  if (end == TorsionPlateEnd::kPinned) {
    a.row(3) << 0, 0, 2, 6 * len;                   // w''(L) = 0
  } else {
    a.row(3) << 0, 1, 2 * len, 3 * len * len;       // w'(L) = phi
    b(3) = end == TorsionPlateEnd::kGuided ? 0.0 : (end == TorsionPlateEnd::kClampedBaseInboard ? theta : -theta);
  }
  const Eigen::Vector4d c = a.fullPivLu().solve(b);
  auto w2 = [&](double x) { return 2 * c(2) + 6 * c(3) * x; };
  BeamSolution s;
  s.force = ei * 6 * c(3);  // shear E I w''' (constant along the plate): sensor 2's force
  s.moment = ei * w2(len);
  const int n = 200;
  const double h = len / n;
  for (int k = 0; k <= n; ++k) {
    const double wk = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
    s.energy += wk * 0.5 * ei * w2(k * h) * w2(k * h) * h / 3.0;
  }
  s.max_moment = ei * std::max(std::abs(w2(0)), std::abs(w2(len)));
  return s;
}

// The Wang 2014 model's torsional plate and lever: L = 80 mm, l = 250 mm (rho = 0.32).
SpringPlate torsional() { return {0.080, 0.100, 0.005, 206e9}; }
constexpr double kLever = 0.250;

TEST(TorsionPlate, SplitMatchesTheBeamEquationForEveryEndCondition) {
  const SpringPlate p = torsional();
  const double k6 = guided_plate_stiffness(p), theta = 1e-5;
  for (TorsionPlateEnd e : {TorsionPlateEnd::kGuided, TorsionPlateEnd::kClampedBaseInboard,
                            TorsionPlateEnd::kClampedBaseOutboard, TorsionPlateEnd::kPinned}) {
    const TorsionPlateSplit s = torsion_plate_split(e, p.length, kLever);
    const BeamSolution b = solve_beam(p, e, kLever, theta);
    // Rotational stiffness from the strain energy: U = 1/2 K_rot theta^2.
    EXPECT_NEAR(2 * b.energy / (theta * theta) / (s.rotation_factor * k6 * kLever * kLever), 1.0, 1e-9)
        << torsion_plate_end_name(e);
    // Sensor 2's force: the end shear.
    EXPECT_NEAR(std::abs(b.force) / (s.force_factor * k6 * kLever * theta), 1.0, 1e-9) << torsion_plate_end_name(e);
    // Largest bending moment.
    EXPECT_NEAR(torsion_plate_max_moment(p, e, kLever, theta) / b.max_moment, 1.0, 1e-9) << torsion_plate_end_name(e);
    // The restoring moment is the force's plus the end moment's share (guided: the guide's).
    if (e != TorsionPlateEnd::kGuided) {
      EXPECT_NEAR(s.rotation_factor, s.force_factor * (1.0 + s.moment_share), 1e-12) << torsion_plate_end_name(e);
    }
  }
  // The figures the model header states for rho = 0.32.
  const TorsionPlateSplit in = torsion_plate_split(TorsionPlateEnd::kClampedBaseInboard, 0.080, kLever);
  const TorsionPlateSplit out = torsion_plate_split(TorsionPlateEnd::kClampedBaseOutboard, 0.080, kLever);
  EXPECT_NEAR(in.rotation_factor, 0.714, 5e-4);
  EXPECT_NEAR(out.rotation_factor, 1.354, 5e-4);
  EXPECT_NEAR(in.moment_share, -0.150, 5e-4);
  EXPECT_NEAR(out.moment_share, 0.167, 5e-4);
  // L << l: every clamped end tends to the guided one.
  const TorsionPlateSplit thin = torsion_plate_split(TorsionPlateEnd::kClampedBaseOutboard, 1e-4, kLever);
  EXPECT_NEAR(thin.rotation_factor, 1.0, 1e-3);
  EXPECT_NEAR(thin.moment_share, 0.0, 1e-3);
}

SpringPlateMachineParams machine(TorsionPlateEnd end) {
  SpringPlateMachineParams p;
  p.rotating_mass = 87.6;
  p.mass_centre_height = 0.18;
  p.inertia = 2.6;
  p.total_mass = 117.6;
  p.lever = kLever;
  p.horizontal_plate_stiffness = 2.2e6;
  p.torsional_plate_stiffness = guided_plate_stiffness(torsional());
  p.torsion_split = torsion_plate_split(end, 0.080, kLever);
  return p;
}

TEST(TorsionPlate, ClosedFormWithTheSplitRecoversTheCoupleAndEq13AloneDoesNot) {
  const double w = rpm_to_rad_per_s(80.0);
  const SpringPlateUnbalance u{2e-3, 0.7, 0.25, 6e-3, -2.0};
  const std::complex<double> ve = u.couple_unbalance * std::polar(1.0, u.couple_phase);
  for (TorsionPlateEnd e : {TorsionPlateEnd::kClampedBaseInboard, TorsionPlateEnd::kClampedBaseOutboard}) {
    const SpringPlateMachineParams p = machine(e);
    const Eigen::Vector2cd fn = sensor_forces(p, hard_bearing_response(p, u, w));
    const SpringPlateUnbalance back = unbalance_from_sensor_forces(p, fn, w, u.height);
    EXPECT_NEAR(back.couple_unbalance / u.couple_unbalance, 1.0, 1e-12);
    // Eq. 13 (F_n2 l taken as the whole moment) reads (F h + T) / (1 + s): V off by a share.
    SpringPlateMachineParams guided = p;
    guided.torsion_split = {};
    const SpringPlateUnbalance eq13 = unbalance_from_sensor_forces(guided, fn, w, u.height);
    const std::complex<double> v13 = eq13.couple_unbalance * std::polar(1.0, eq13.couple_phase);
    EXPECT_GT(std::abs(v13 - ve) / std::abs(ve), 0.1) << torsion_plate_end_name(e);
  }
}

TEST(SpringPlateSensor, SensorOneReadsItsOwnPlatesShare) {
  // Plate 1 1 % stiffer than the mean: sensor 1 in plate 1 reads k5,1 / (k5,1 + k5,2) F =
  // 0.505 F, and the closed form's U = 2 F_n1 / w^2 is 1 % high.
  SpringPlateMachineParams p = machine(TorsionPlateEnd::kGuided);
  p.sensor_1_plate_stiffness = 1.01 * p.horizontal_plate_stiffness;
  const double w = rpm_to_rad_per_s(80.0);
  const SpringPlateUnbalance u{2e-3, 0.7, 0.25, 0.0, 0.0};
  const Eigen::Vector2cd x = hard_bearing_response(p, u, w);
  const Eigen::Vector2cd fn = sensor_forces(p, x);
  const double f = u.static_unbalance * w * w;  // the centrifugal force the pair carries
  EXPECT_NEAR(std::abs(fn(0)) / f, 1.01 / 2.0, 1e-12);
  EXPECT_NEAR(unbalance_from_sensor_forces(p, fn, w, u.height).static_unbalance / u.static_unbalance, 1.01, 1e-12);
  // The stiffness of the pair is unchanged: the motion is that of 2 k5.
  EXPECT_NEAR(std::abs(x(0)) * 2 * p.horizontal_plate_stiffness / f, 1.0, 1e-12);
  // Equal plates: the ratio is 1/2 whatever k5, so no stiffness error reaches the closed form.
  SpringPlateMachineParams q = p;
  q.sensor_1_plate_stiffness = 0.0;
  q.horizontal_plate_stiffness *= 1.3;
  EXPECT_NEAR(unbalance_from_sensor_forces(q, sensor_forces(q, hard_bearing_response(q, u, w)), w, u.height)
                  .static_unbalance / u.static_unbalance, 1.0, 1e-12);
}

}  // namespace
}  // namespace poise::models
