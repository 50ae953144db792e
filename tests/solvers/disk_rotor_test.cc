// Disk rotor model (Yang 2015 Eq. 17, derived anew): energy conservation, small-oscillation
// frequencies against the linearization and closed forms, holding torque at rest.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "models/disk_rotor.h"
#include "solvers/cvode_integrator.h"

namespace poise::models {
namespace {

constexpr double kPi = 3.14159265358979323846;

DiskRotorParams conservative() {
  DiskRotorParams p;
  p.mass = 2.0;
  p.inertia = 4e-3;
  p.eccentricity = 3e-4;
  p.eccentricity_angle = 0.7;
  p.support_stiffness = 4e6;
  p.torsion_stiffness = 0.05;
  p.torsion_zero = 0.0;
  return p;
}

struct Free {
  DiskRotorParams p;
  GimbalGravity g;
  double torque = 0.0;
};

int free_rhs(double, const double* y, double* ydot, void* user) {
  const auto* f = static_cast<const Free*>(user);
  const DiskState s{y[0], y[1], y[2], y[3], y[4], y[5]};
  const auto a = disk_accelerations(f->p, f->g, s, f->torque);
  ydot[0] = y[1];
  ydot[1] = a[0];
  ydot[2] = y[3];
  ydot[3] = a[1];
  ydot[4] = y[5];
  ydot[5] = a[2];
  return 0;
}

TEST(DiskRotor, EnergyConservedWithoutDriveAndDamping) {
  Free f{conservative(), gravity_in_gimbal(9.80665, 0.3), 0.0};
  solvers::CvodeOptions opt;
  opt.rtol = 1e-11;
  opt.atol = 1e-14;
  opt.max_step = 1e-4;
  solvers::CvodeIntegrator integ(6, free_rhs, &f, opt);
  // A large swing (0.5 rad, 3 rad/s) so that every coupling term works.
  const std::vector<double> y0 = {0.5, 3.0, 1e-5, 0.0, -2e-5, 1e-3};
  integ.reset(0.0, y0);
  DiskState s0{};
  std::copy(y0.begin(), y0.end(), s0.begin());
  const double e0 = disk_energy(f.p, f.g, s0);
  double worst = 0.0;
  for (int k = 1; k <= 20; ++k) {
    integ.advance(0.1 * k, 10.0, false);
    DiskState s{};
    std::copy(integ.state().begin(), integ.state().end(), s.begin());
    worst = std::max(worst, std::abs(disk_energy(f.p, f.g, s) - e0));
  }
  // Energy scale: the kinetic energy J w^2 / 2 = 0.018 J.
  EXPECT_LT(worst, 1e-8) << "energy drift " << worst << " J";
}

TEST(DiskRotor, IntegratorThatCannotBeSetUpThrowsAndFreesWhatItMade) {
  // A check that fails half-way (the context, vectors and CVODE memory already made): the
  // constructor throws a poise::Error and its handles are freed by their owners (the fuzz
  // build's LeakSanitizer sees a leak otherwise); a good integrator made after it works.
  Free f{conservative(), gravity_in_gimbal(9.80665, 0.3), 0.0};
  solvers::CvodeOptions bad;
  bad.atol_per_state = {1e-9, 1e-9};  // 2 entries for 6 states
  for (int k = 0; k < 50; ++k) EXPECT_THROW(solvers::CvodeIntegrator(6, free_rhs, &f, bad), poise::Error);
  solvers::CvodeIntegrator good(6, free_rhs, &f, solvers::CvodeOptions{});
  good.reset(0.0, std::vector<double>{0.1, 0.0, 0.0, 0.0, 0.0, 0.0});
  EXPECT_GT(good.advance(0.01, 1.0, false), 0.0);
}

TEST(DiskRotor, HoldingTorqueAtRest) {
  const DiskRotorParams p = conservative();
  for (double theta : {0.0, 0.5, 1.7, 3.0, 4.4}) {
    const GimbalGravity g = gravity_in_gimbal(9.80665, theta);
    const double phi = 0.01;
    const double m_hold = holding_torque(p, g, phi);
    // m g e sin(theta + phi + eps) + k_CR phi
    EXPECT_NEAR(m_hold, p.mass * 9.80665 * p.eccentricity * std::sin(theta + phi + p.eccentricity_angle) +
                            p.torsion_stiffness * phi, 1e-15);
    const auto d = static_deflection(p, g);
    const DiskState s{phi, 0.0, d[0], 0.0, d[1], 0.0};
    const auto a = disk_accelerations(p, g, s, m_hold);
    EXPECT_NEAR(a[0], 0.0, 1e-11);
    EXPECT_NEAR(a[1], 0.0, 1e-9);
    EXPECT_NEAR(a[2], 0.0, 1e-9);
  }
}

TEST(DiskRotor, GravityTiltRotatesTheVector) {
  const GimbalGravity g0 = gravity_in_gimbal(9.8, 0.4);
  EXPECT_NEAR(g0.gy, 9.8 * std::cos(0.4), 1e-12);
  EXPECT_NEAR(g0.gz, -9.8 * std::sin(0.4), 1e-12);
  // Tilt towards the gravity direction removes cos(tilt) of it from the plane.
  const double tilt = 0.01;
  const GimbalGravity g1 = gravity_in_gimbal(9.8, 0.0, tilt, 0.0);
  EXPECT_NEAR(g1.gy, 9.8 * std::cos(tilt), 1e-12);
  EXPECT_NEAR(g1.gz, 0.0, 1e-12);
  // Tilt across it changes nothing in the plane.
  const GimbalGravity g2 = gravity_in_gimbal(9.8, 0.0, tilt, kPi / 2);
  EXPECT_NEAR(g2.gy, 9.8, 1e-12);
}

// Numerical Jacobian of the 6-state system at s.
Eigen::MatrixXd jacobian(Free& f, const DiskState& s) {
  Eigen::MatrixXd j(6, 6);
  double y[6], fp[6], fm[6];
  for (int c = 0; c < 6; ++c) {
    const double h = 1e-7 * std::max(1.0, std::abs(s[static_cast<std::size_t>(c)])) * (c >= 2 ? 1e-3 : 1.0);
    for (int k = 0; k < 6; ++k) y[k] = s[static_cast<std::size_t>(k)];
    y[c] += h;
    free_rhs(0, y, fp, &f);
    y[c] -= 2 * h;
    free_rhs(0, y, fm, &f);
    for (int r = 0; r < 6; ++r) j(r, c) = (fp[r] - fm[r]) / (2 * h);
  }
  return j;
}

std::vector<double> frequencies(const Eigen::MatrixXd& j) {
  Eigen::EigenSolver<Eigen::MatrixXd> es(j);
  std::vector<double> w;
  for (int k = 0; k < 6; ++k) {
    if (es.eigenvalues()[k].imag() > 0) w.push_back(es.eigenvalues()[k].imag());
  }
  std::sort(w.begin(), w.end());
  return w;
}

TEST(DiskRotor, LinearizationWithoutEccentricityIsDecoupled) {
  Free f{conservative(), {0.0, 0.0}, 0.0};
  f.p.eccentricity = 0.0;
  const auto w = frequencies(jacobian(f, {0, 0, 0, 0, 0, 0}));
  ASSERT_EQ(w.size(), 3u);
  EXPECT_NEAR(w[0], std::sqrt(f.p.torsion_stiffness / f.p.inertia), 1e-4);
  EXPECT_NEAR(w[1], std::sqrt(f.p.support_stiffness / f.p.mass), 1e-3);
  EXPECT_NEAR(w[2], std::sqrt(f.p.support_stiffness / f.p.mass), 1e-3);
}

TEST(DiskRotor, SimulatedPendulumFrequencyMatchesLinearization) {
  Free f{conservative(), gravity_in_gimbal(9.80665, 0.2), 0.0};
  f.p.eccentricity = 2e-3;  // a pendulum stiffer than the cable
  // Equilibrium: k_CR phi + m g e sin(theta + phi + eps) = 0, solved by Newton.
  const double mge = f.p.mass * 9.80665 * f.p.eccentricity;
  double phi = 0.0;
  for (int it = 0; it < 50; ++it) {
    const double r = f.p.torsion_stiffness * phi + mge * std::sin(0.2 + phi + f.p.eccentricity_angle);
    const double d = f.p.torsion_stiffness + mge * std::cos(0.2 + phi + f.p.eccentricity_angle);
    phi -= r / d;
  }
  // Static support deflection at equilibrium (F_y = F_z = 0 at rest).
  const DiskState eq{phi, 0, f.p.mass * f.g.gy / f.p.support_stiffness, 0,
                     f.p.mass * f.g.gz / f.p.support_stiffness, 0};
  const auto a = disk_accelerations(f.p, f.g, eq, 0.0);
  EXPECT_NEAR(a[0], 0.0, 1e-9);
  const auto w = frequencies(jacobian(f, eq));
  ASSERT_EQ(w.size(), 3u);
  // Rigid-support closed form for the slow mode.
  const double w_rigid = std::sqrt((f.p.torsion_stiffness + mge * std::cos(0.2 + phi + f.p.eccentricity_angle)) /
                                   (f.p.inertia + f.p.mass * f.p.eccentricity * f.p.eccentricity));
  EXPECT_NEAR(w[0] / w_rigid, 1.0, 1e-4);
  // The printed Eq. 17's (J + 2 m e^2) (J about the rotation centre, m e^2 counted twice)
  // would give a frequency 0.1% lower here, ten times the tolerance above.
  const double w_printed = std::sqrt((f.p.torsion_stiffness + mge * std::cos(0.2 + phi + f.p.eccentricity_angle)) /
                                     (f.p.inertia + 2 * f.p.mass * f.p.eccentricity * f.p.eccentricity));
  EXPECT_GT(std::abs(w[0] / w_printed - 1.0), 5e-4);
  // The nonlinear simulation of a small swing: period from upward zero crossings.
  solvers::CvodeOptions opt;
  opt.rtol = 1e-10;
  opt.atol = 1e-14;
  solvers::CvodeIntegrator integ(6, free_rhs, &f, opt);
  std::vector<double> y0(eq.begin(), eq.end());
  y0[0] += 1e-4;
  integ.reset(0.0, y0);
  std::vector<double> crossings;
  double prev = y0[0] - phi, t_prev = 0.0;
  const double period = 2 * kPi / w[0];
  std::vector<double> y(6);
  for (int k = 1; k <= 20000 && crossings.size() < 6; ++k) {
    const double t = k * period / 2000.0;
    integ.advance(t, 100 * period, false);
    const double cur = integ.state()[0] - phi;
    if (prev < 0 && cur >= 0) crossings.push_back(t_prev + (t - t_prev) * (-prev) / (cur - prev));
    prev = cur;
    t_prev = t;
  }
  ASSERT_GE(crossings.size(), 6u);
  const double measured = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  EXPECT_NEAR(measured / period, 1.0, 1e-4);
}

}  // namespace
}  // namespace poise::models
