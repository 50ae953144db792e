// Spring-plate balancing machine (Wang & Wang 2014, Eq. 8 derived anew): plate stiffness by
// hand, natural frequencies against closed forms, energy conservation, steady state against
// a long time integration, the hard-bearing limit and Eqs. 1-2, 13, 14, 17 corrected.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/units.h"
#include "models/spring_plate_machine.h"

namespace poise::models {
namespace {

constexpr double kPi = 3.14159265358979323846;
using cd = std::complex<double>;
using State = std::array<double, 4>;

// Plausible plates of spring steel (60Si2Mn, E = 206 GPa); dimensions are our choice, the
// paper gives none. Horizontal plates 100 x 150 x 4 mm, torsional plate 80 x 100 x 5 mm.
SpringPlate horizontal_plate() { return {0.100, 0.150, 0.004, 206e9}; }
SpringPlate torsional_plate() { return {0.080, 0.100, 0.005, 206e9}; }

// Wang 2014 Sec. 5: standard rotor M_R = 47.6 kg, H_R = 510 mm, D = 100 mm; testing surface 1
// at 150 mm above the shaft, surfaces 50 mm apart (1..8 span 350 mm). Assumed: rotor bottom
// 70 mm above the shaft (surfaces centred on the rotor), so its centre is at 325 mm; a
// spindle/support of 40 kg centred on the shaft with 0.5 kg m^2; a board and shaft of 30 kg
// that only translate; lever l = 250 mm.
SpringPlateMachineParams wang2014() {
  const double m_r = 47.6, h_r = 0.510, r_r = 0.050, z_r = 0.070 + h_r / 2;
  const double j_r = m_r * (3 * r_r * r_r + h_r * h_r) / 12;  // solid cylinder, transverse axis
  const double m_s = 40.0, z_s = 0.0, j_s = 0.5;
  SpringPlateMachineParams p;
  p.rotating_mass = m_r + m_s;
  p.mass_centre_height = (m_r * z_r + m_s * z_s) / p.rotating_mass;
  const double H = p.mass_centre_height;
  p.inertia = j_r + m_r * (z_r - H) * (z_r - H) + j_s + m_s * (z_s - H) * (z_s - H);
  p.total_mass = p.rotating_mass + 30.0;
  p.lever = 0.250;
  p.horizontal_plate_stiffness = guided_plate_stiffness(horizontal_plate());
  p.torsional_plate_stiffness = guided_plate_stiffness(torsional_plate());
  return p;
}

// Damping ratio zeta on each uncoupled mode.
SpringPlateMachineParams with_damping(SpringPlateMachineParams p, double zeta) {
  const Eigen::Matrix2d m = mass_matrix(p), k = stiffness_matrix(p);
  p.damping_x = 2 * zeta * std::sqrt(k(0, 0) * m(0, 0));
  p.damping_theta = 2 * zeta * std::sqrt(k(1, 1) * m(1, 1));
  return p;
}

// Classical fixed-step RK4 on spring_plate_rhs.
void rk4_step(SpringPlateRhsData& d, double t, double h, State& y) {
  State k1, k2, k3, k4, tmp;
  auto f = [&](double tt, const State& yy, State& out) {
    ASSERT_EQ(spring_plate_rhs(tt, yy.data(), out.data(), &d), 0);
  };
  f(t, y, k1);
  for (int i = 0; i < 4; ++i) tmp[i] = y[i] + 0.5 * h * k1[i];
  f(t + 0.5 * h, tmp, k2);
  for (int i = 0; i < 4; ++i) tmp[i] = y[i] + 0.5 * h * k2[i];
  f(t + 0.5 * h, tmp, k3);
  for (int i = 0; i < 4; ++i) tmp[i] = y[i] + h * k3[i];
  f(t + h, tmp, k4);
  for (int i = 0; i < 4; ++i) y[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
}

// ---- spring plates ------------------------------------------------------------------------

TEST(SpringPlate, GuidedStiffnessStressAndDeflectionByHand) {
  const SpringPlate pl = horizontal_plate();
  // I = 0.15 * 0.004^3 / 12 = 8e-10 m^4; k = 12 * 206e9 * 8e-10 / 0.1^3 = 1.9776e6 N/m.
  EXPECT_NEAR(plate_second_moment(pl) / 8e-10, 1.0, 1e-12);
  EXPECT_NEAR(guided_plate_stiffness(pl) / 1.9776e6, 1.0, 1e-12);
  // 100 N at the guided end: clamp moment F L / 2 = 5 N m, sigma = M (t/2) / I = 12.5 MPa.
  EXPECT_NEAR(guided_plate_max_stress(pl, 100.0) / 12.5e6, 1.0, 1e-12);
  EXPECT_NEAR(guided_plate_max_stress(pl, -100.0) / 12.5e6, 1.0, 1e-12);
  EXPECT_NEAR(guided_plate_deflection(pl, 100.0) / (100.0 / 1.9776e6), 1.0, 1e-12);
  // A guided end is 4 times stiffer than a free (cantilever, 3 E I / L^3) one.
  EXPECT_NEAR(guided_plate_stiffness(pl) / (3 * 206e9 * 8e-10 / 1e-3), 4.0, 1e-12);
  // Rotational stiffness at lever l: k6 l^2.
  EXPECT_DOUBLE_EQ(rotational_stiffness(2e6, 0.25), 2e6 * 0.0625);
}

TEST(SpringPlate, UnitsAreConsistent) {
  // The same plate written with units, parsed to SI...
  const SpringPlate pl{units::parse_as("100 mm", units::kLength), units::parse_as("150 mm", units::kLength),
                       units::parse_as("4 mm", units::kLength), units::parse_as("206 GPa", units::kPressure)};
  const double k = guided_plate_stiffness(pl);
  // ...against the hand computation in the N, mm, MPa system: E w t^3 / L^3 in N/mm.
  const double k_n_per_mm = 206000.0 * 150.0 * 64.0 / 1e6;  // 1977.6 N/mm
  constexpr units::Dimension kStiffness{{0, 1, -2, 0, 0, 0}};  // N/m = kg s^-2
  EXPECT_NEAR(k / units::parse_as("1977.6 N/mm", kStiffness), 1.0, 1e-12);
  EXPECT_NEAR(k_n_per_mm, 1977.6, 1e-9);
  // k = E w t^3 / L^3 has the dimension of E times a length: scaling every length by 10 scales k by 10.
  const SpringPlate big{1.0, 1.5, 0.04, 206e9};
  EXPECT_NEAR(guided_plate_stiffness(big) / k, 10.0, 1e-12);
  // Stress is force over area: the same force on the tenfold plate gives 1/100.
  EXPECT_NEAR(guided_plate_max_stress(big, 100.0) / guided_plate_max_stress(pl, 100.0), 0.01, 1e-15);
}

TEST(SpringPlate, RefusesNonPositiveDimensionsNamingTheField) {
  SpringPlate pl = horizontal_plate();
  pl.thickness = 0.0;
  try {
    guided_plate_stiffness(pl);
    FAIL() << "expected poise::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("thickness = 0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("expected a finite value > 0"), std::string::npos) << e.what();
  }
}

TEST(SpringPlateMachine, ValidationMessages) {
  SpringPlateMachineParams p = wang2014();
  p.rotating_mass = p.total_mass + 1.0;
  try {
    validate(p);
    FAIL() << "expected poise::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("rotating_mass"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("m <= M"), std::string::npos) << e.what();
  }
  p = wang2014();
  p.gravity = 9.80665;
  p.torsional_plate_stiffness = 0.5 * p.rotating_mass * p.gravity * p.mass_centre_height / (p.lever * p.lever);
  try {
    validate(p);
    FAIL() << "expected poise::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("K_rot - m g H"), std::string::npos) << e.what();
  }
}

// ---- natural frequencies ------------------------------------------------------------------

TEST(SpringPlateMachine, UncoupledLimitFrequencies) {
  SpringPlateMachineParams p = wang2014();
  p.mass_centre_height = 0.0;  // m H -> 0: no inertial coupling
  const NaturalFrequencies f = natural_frequencies(p);
  const double wx = std::sqrt(2 * p.horizontal_plate_stiffness / p.total_mass);
  const double wt = std::sqrt(p.torsional_plate_stiffness * p.lever * p.lever / p.inertia);
  EXPECT_NEAR(f.omega_1 / std::min(wx, wt), 1.0, 1e-12);
  EXPECT_NEAR(f.omega_2 / std::max(wx, wt), 1.0, 1e-12);
  // Small m H: the shift is second order in the coupling, (m H)^2 / (M J_total) times
  // w^2 / |w_x^2 - w_t^2| (perturbation of a 2x2 eigenproblem); it vanishes as H -> 0.
  for (double h : {1e-3, 1e-4}) {
    p.mass_centre_height = h;
    const NaturalFrequencies g = natural_frequencies(p);
    const double coupling = std::pow(p.rotating_mass * h, 2) / (p.total_mass * (p.inertia + p.rotating_mass * h * h));
    const double bound = coupling * std::max(wx, wt) * std::max(wx, wt) / std::abs(wx * wx - wt * wt);
    EXPECT_LT(std::abs(g.omega_1 / std::min(g.omega_x, g.omega_theta) - 1.0), bound);
    EXPECT_GT(std::abs(g.omega_1 / std::min(g.omega_x, g.omega_theta) - 1.0), 0.01 * bound);
  }
}

TEST(SpringPlateMachine, CoupledFrequenciesSolveTheCharacteristicEquation) {
  const SpringPlateMachineParams p = wang2014();
  const NaturalFrequencies f = natural_frequencies(p);
  const Eigen::Matrix2d m = mass_matrix(p), k = stiffness_matrix(p);
  // det(K - l M) = a l^2 + b l + c = 0 written out by hand.
  const double a = m(0, 0) * m(1, 1) - m(0, 1) * m(0, 1);
  const double b = -(k(0, 0) * m(1, 1) + k(1, 1) * m(0, 0));
  const double c = k(0, 0) * k(1, 1);
  const double disc = std::sqrt(b * b - 4 * a * c);
  EXPECT_NEAR(f.omega_1 / std::sqrt((-b - disc) / (2 * a)), 1.0, 1e-12);
  EXPECT_NEAR(f.omega_2 / std::sqrt((-b + disc) / (2 * a)), 1.0, 1e-12);
  // Inertial coupling pushes the coupled frequencies outside the uncoupled ones (Eq. 9's).
  EXPECT_LT(f.omega_1, std::min(f.omega_x, f.omega_theta));
  EXPECT_GT(f.omega_2, std::max(f.omega_x, f.omega_theta));
  // Modes are M-orthonormal and diagonalize K.
  const Eigen::Matrix2d pm = f.modes.transpose() * m * f.modes, pk = f.modes.transpose() * k * f.modes;
  EXPECT_NEAR(pm(0, 0), 1.0, 1e-12);
  EXPECT_NEAR(pm(0, 1), 0.0, 1e-12);
  EXPECT_NEAR(pk(0, 0) / (f.omega_1 * f.omega_1), 1.0, 1e-12);
  EXPECT_NEAR(pk(1, 1) / (f.omega_2 * f.omega_2), 1.0, 1e-12);
  EXPECT_NEAR(pk(0, 1) / pk(1, 1), 0.0, 1e-12);

  // Report for Wang 2014 plausible values, gravity off (Eq. 8) and on.
  SpringPlateMachineParams pg = p;
  pg.gravity = 9.80665;
  const NaturalFrequencies fg = natural_frequencies(pg);
  std::printf(
      "[ wang2014 ] M = %.1f kg, m = %.1f kg, H = %.4f m, J = %.3f kg m^2, k5 = %.4g N/m, k6 = %.4g N/m, "
      "k6 l^2 = %.4g N m/rad\n"
      "[ wang2014 ] uncoupled f_x = %.2f Hz, f_theta = %.2f Hz; coupled f_1 = %.2f Hz, f_2 = %.2f Hz; "
      "with gravity f_1 = %.2f Hz, f_2 = %.2f Hz (m g H / k6 l^2 = %.3g)\n",
      p.total_mass, p.rotating_mass, p.mass_centre_height, p.inertia, p.horizontal_plate_stiffness,
      p.torsional_plate_stiffness, k(1, 1), f.omega_x / (2 * kPi), f.omega_theta / (2 * kPi),
      f.omega_1 / (2 * kPi), f.omega_2 / (2 * kPi), fg.omega_1 / (2 * kPi), fg.omega_2 / (2 * kPi),
      p.rotating_mass * 9.80665 * p.mass_centre_height / k(1, 1));
  EXPECT_LT(fg.omega_1, f.omega_1);  // the pendulum term softens the torsional mode
}

// ---- time domain --------------------------------------------------------------------------

TEST(SpringPlateMachine, RhsReportsNullUserDataAndIsZeroAtRest) {
  double y[4] = {0, 0, 0, 0}, yd[4] = {1, 1, 1, 1};
  EXPECT_EQ(spring_plate_rhs(0.0, y, yd, nullptr), -1);
  SpringPlateRhsData d{wang2014(), {}, 8.0};
  EXPECT_EQ(spring_plate_rhs(0.3, y, yd, &d), 0);
  for (double v : yd) EXPECT_EQ(v, 0.0);
}

TEST(SpringPlateMachine, FreeUndampedEnergyConservedOver100Periods) {
  SpringPlateRhsData d{wang2014(), {}, 0.0};
  d.params.gravity = 9.80665;  // the pendulum term is conservative too
  const NaturalFrequencies f = natural_frequencies(d.params);
  const double h = 2 * kPi / f.omega_2 / 1000.0;
  const long steps = std::lround(100 * 2 * kPi / f.omega_1 / h);
  State y{2e-5, 1e-3, -3e-5, 4e-3};  // both modes excited
  const double e0 = mechanical_energy(d.params, y.data());
  double worst = 0.0;
  for (long n = 0; n < steps; ++n) {
    rk4_step(d, static_cast<double>(n) * h, h, y);
    worst = std::max(worst, std::abs(mechanical_energy(d.params, y.data()) - e0) / e0);
  }
  EXPECT_LT(worst, 1e-8) << "relative energy drift over 100 periods of the slow mode";
}

TEST(SpringPlateMachine, SteadyStateMatchesLongIntegration) {
  const double zeta = 0.05;
  SpringPlateRhsData d{with_damping(wang2014(), zeta), {}, 0.0};
  d.unbalance = {1e-3, 0.4, 0.30, 5e-3, -1.1};  // U, a3, h, V, a4
  const NaturalFrequencies f = natural_frequencies(d.params);
  d.omega = 0.6 * f.omega_1;  // well inside the dynamic range: the hard-bearing limit is poor here
  const Eigen::Vector2cd x_exact = steady_state_response(d.params, d.unbalance, d.omega);
  const Eigen::Vector2cd x_hb = hard_bearing_response(d.params, d.unbalance, d.omega);
  EXPECT_GT(std::abs(x_exact(0) / x_hb(0) - 1.0), 0.1);

  const double period = 2 * kPi / d.omega;
  const double h = 2 * kPi / f.omega_2 / 400.0;
  const double t_settle = 25.0 / (zeta * f.omega_1);  // transients decay as exp(-zeta w t)
  const int per_period = static_cast<int>(std::ceil(period / h));
  const double hp = period / per_period;  // whole periods in whole steps
  const long settle_steps = std::lround(std::ceil(t_settle / period)) * per_period;
  State y{0, 0, 0, 0};
  for (long n = 0; n < settle_steps; ++n) rk4_step(d, static_cast<double>(n) * hp, hp, y);
  // Fourier coefficient at omega over 4 whole periods (rectangle rule is exact for a sinusoid).
  cd cx = 0.0, ct = 0.0;
  double worst_x = 0.0, worst_t = 0.0;
  const int samples = 4 * per_period;
  for (int k = 0; k < samples; ++k) {
    const double tk = static_cast<double>(settle_steps + k) * hp;
    const cd e = std::polar(1.0, -d.omega * tk);
    cx += y[0] * e;
    ct += y[2] * e;
    worst_x = std::max(worst_x, std::abs(y[0] - std::real(x_exact(0) / e)));
    worst_t = std::max(worst_t, std::abs(y[2] - std::real(x_exact(1) / e)));
    rk4_step(d, tk, hp, y);
  }
  cx *= 2.0 / samples;
  ct *= 2.0 / samples;
  EXPECT_NEAR(std::abs(cx) / std::abs(x_exact(0)), 1.0, 1e-3);
  EXPECT_NEAR(std::abs(ct) / std::abs(x_exact(1)), 1.0, 1e-3);
  EXPECT_NEAR(std::arg(cx / x_exact(0)), 0.0, 1e-3);
  EXPECT_NEAR(std::arg(ct / x_exact(1)), 0.0, 1e-3);
  EXPECT_LT(worst_x / std::abs(x_exact(0)), 1e-3);
  EXPECT_LT(worst_t / std::abs(x_exact(1)), 1e-3);
}

TEST(SpringPlateMachine, Eq14CorrectedIsTheExactUndampedSolution) {
  const SpringPlateMachineParams p = wang2014();
  const SpringPlateUnbalance u{1e-3, 0.2, 0.35, 4e-3, 1.3};
  const double w = 0.4 * natural_frequencies(p).omega_1;
  const double M = p.total_mass, m = p.rotating_mass, H = p.mass_centre_height, J = p.inertia;
  const double k1 = 2 * p.horizontal_plate_stiffness, k2 = p.torsional_plate_stiffness * p.lever * p.lever;
  const double w2 = w * w;
  const cd F = u.static_unbalance * w2 * std::polar(1.0, u.static_phase);
  const cd T = u.couple_unbalance * w2 * std::polar(1.0, u.couple_phase);
  const cd fh = F * u.height + T;
  const double D = (k1 - M * w2) * (k2 - (J + m * H * H) * w2) - m * m * H * H * w2 * w2;
  const cd x = (F * (k2 - (J + m * H * H) * w2) + m * H * w2 * fh) / D;
  const cd th = ((k1 - M * w2) * fh + m * H * w2 * F) / D;
  const Eigen::Vector2cd s = steady_state_response(p, u, w);
  EXPECT_NEAR(std::abs(s(0) / x - 1.0), 0.0, 1e-12);
  EXPECT_NEAR(std::abs(s(1) / th - 1.0), 0.0, 1e-12);
  // The printed slip (2 k - m w^2) for (2 k - M w^2) gives another answer at this speed.
  const double D_printed = (k1 - m * w2) * (k2 - (J + m * H * H) * w2) - m * m * H * H * w2 * w2;
  EXPECT_GT(std::abs(D_printed / D - 1.0), 1e-3);
}

// ---- hard-bearing limit -------------------------------------------------------------------

TEST(SpringPlateMachine, HardBearingSeparationAtWang2014Speed) {
  const SpringPlateMachineParams p = with_damping(wang2014(), 0.02);
  const double w = rpm_to_rad_per_s(80.0);  // test speed n_1 = 80 r/min
  const double U = 0.020 * 0.050;           // test mass m_1 = 20 g at r_1 = 50 mm
  std::vector<Eigen::Vector2cd> lim, ex;
  std::vector<double> heights;
  for (int s = 1; s <= 8; ++s) {
    const double h = 0.150 + 0.050 * (s - 1);  // testing surfaces 1..8
    const SpringPlateUnbalance u{U, 0.0, h, 0.0, 0.0};
    heights.push_back(h);
    lim.push_back(hard_bearing_response(p, u, w));
    ex.push_back(steady_state_response(p, u, w));
  }
  double x_spread = 0.0, th_spread = 0.0, dev_x = 0.0, dev_t = 0.0;
  for (std::size_t i = 0; i < heights.size(); ++i) {
    // In the limit: sensor 1 independent of h, sensor 2 proportional to h (Eq. 11 corrected).
    EXPECT_EQ(lim[i](0), lim[0](0));
    EXPECT_NEAR(std::abs(lim[i](1) / heights[i] / (lim[0](1) / heights[0]) - 1.0), 0.0, 1e-14);
    EXPECT_NEAR(std::abs(lim[i](0)) / (U * w * w / (2 * p.horizontal_plate_stiffness)), 1.0, 1e-14);
    // Exact at 80 r/min: how far from the limit.
    x_spread = std::max(x_spread, std::abs(ex[i](0) / ex[0](0) - 1.0));
    th_spread = std::max(th_spread, std::abs(ex[i](1) / heights[i] / (ex[0](1) / heights[0]) - 1.0));
    dev_x = std::max(dev_x, std::abs(ex[i](0) / lim[i](0) - 1.0));
    dev_t = std::max(dev_t, std::abs(ex[i](1) / lim[i](1) - 1.0));
  }
  const HardBearingCheck c = check_hard_bearing(p, w);
  std::printf(
      "[ wang2014 ] 80 r/min: f_1 / n = %.1f; static unbalance at surfaces 1-8: sensor 1 varies by %.3g, "
      "sensor 2 / h by %.3g; exact vs limit: x %.3g, theta %.3g\n[ wang2014 ] %s\n",
      c.ratio, x_spread, th_spread, dev_x, dev_t, c.message.c_str());
  EXPECT_TRUE(c.ok) << c.message;
  // The exact response depends on h to first order in w^2 / w_n^2, as the corrected Eq. 14
  // predicts: x through m H h w^2 beside k6 l^2, theta / h through m H w^2 / h beside 2 k5.
  const double mhw2 = p.rotating_mass * p.mass_centre_height * w * w;
  const double x_pred = mhw2 * (heights.back() - heights.front()) /
                        (p.torsional_plate_stiffness * p.lever * p.lever - (p.inertia + p.rotating_mass *
                         p.mass_centre_height * p.mass_centre_height) * w * w + mhw2 * heights.front());
  const double th_pred = mhw2 * (1 / heights.front() - 1 / heights.back()) /
                         (2 * p.horizontal_plate_stiffness - p.total_mass * w * w + mhw2 / heights.back());
  EXPECT_NEAR(x_spread / x_pred, 1.0, 2e-2);
  EXPECT_NEAR(th_spread / th_pred, 1.0, 2e-2);
  // Both about 1e-3: the separation holds to 0.1 % at 80 r/min with these plates, and the
  // response is within (n / f_1)^2 ~ 0.3 % of the limit.
  EXPECT_LT(x_spread, 2e-3);
  EXPECT_LT(th_spread, 2e-3);
  EXPECT_LT(dev_x, 2.0 / (c.ratio * c.ratio));
  EXPECT_LT(dev_t, 2.0 / (c.ratio * c.ratio));
  // Near resonance the check fails and says what to do.
  const HardBearingCheck bad = check_hard_bearing(p, 0.5 * natural_frequencies(p).omega_1);
  EXPECT_FALSE(bad.ok);
  EXPECT_NE(bad.message.find("stiffen the spring plates"), std::string::npos) << bad.message;
}

TEST(SpringPlateMachine, CoupleCrossTalkIntoSensorOneIsEq15sTerm) {
  const SpringPlateMachineParams p = wang2014();
  const double w = rpm_to_rad_per_s(80.0);
  const SpringPlateUnbalance v{0.0, 0.0, 0.0, 0.1, 0.0};  // pure couple 0.1 kg m^2
  const cd x = steady_state_response(p, v, w)(0);
  const double k2 = p.torsional_plate_stiffness * p.lever * p.lever;
  const double eq15 = p.rotating_mass * p.mass_centre_height * 0.1 * std::pow(w, 4) /
                      (2 * p.horizontal_plate_stiffness * k2);
  EXPECT_NEAR(std::real(x) / eq15, 1.0, 1e-2);
  EXPECT_EQ(hard_bearing_response(p, v, w)(0), cd(0.0));  // absent in the limit
}

TEST(SpringPlateMachine, Eq17And13CorrectedRecoverTheUnbalance) {
  SpringPlateMachineParams p = wang2014();
  const double w = rpm_to_rad_per_s(80.0);
  const SpringPlateUnbalance u{2e-3, 0.7, 0.25, 6e-3, -2.0};
  const Eigen::Vector2cd fn = sensor_forces(p, hard_bearing_response(p, u, w));
  // Eq. 17 corrected (complex amplitudes): F_n1 = U w^2 / 2, F_n2 l = (U h + V) w^2.
  const cd ue = u.static_unbalance * std::polar(1.0, u.static_phase);
  const cd ve = u.couple_unbalance * std::polar(1.0, u.couple_phase);
  EXPECT_NEAR(std::abs(fn(0) / (ue * w * w / 2.0) - 1.0), 0.0, 1e-12);
  EXPECT_NEAR(std::abs(fn(1) * p.lever / ((ue * u.height + ve) * w * w) - 1.0), 0.0, 1e-12);
  // Eq. 13 corrected inverts it.
  const SpringPlateUnbalance back = unbalance_from_sensor_forces(p, fn, w, u.height);
  EXPECT_NEAR(back.static_unbalance, u.static_unbalance, 1e-15);
  EXPECT_NEAR(back.static_phase, u.static_phase, 1e-12);
  EXPECT_NEAR(back.couple_unbalance, u.couple_unbalance, 1e-14);
  EXPECT_NEAR(back.couple_phase, u.couple_phase, 1e-12);
  // Eq. 13 as printed, (F_n2 l - 2 F_n1) / w^2, misses V by far more than the tolerance.
  const cd v_printed = (fn(1) * p.lever - 2.0 * fn(0)) / (w * w);
  EXPECT_GT(std::abs(v_printed - ve) / std::abs(ve), 0.1);
  // From the exact response at 80 r/min the same inversion is good to the hard-bearing error.
  const SpringPlateUnbalance near = unbalance_from_sensor_forces(p, sensor_forces(p, steady_state_response(p, u, w)), w, u.height);
  EXPECT_NEAR(near.static_unbalance / u.static_unbalance, 1.0, 1e-2);
  EXPECT_NEAR(near.couple_unbalance / u.couple_unbalance, 1.0, 1e-2);
}

// ---- Eqs. 1-2 -----------------------------------------------------------------------------

TEST(SpringPlateMachine, UnbalanceFromPlaneMasses) {
  const double m = 0.160, r = 0.075, z1 = 0.20, z2 = 0.45, d = z2 - z1;
  // Opposite: pure couple m r d about any height.
  const std::array<PlaneMass, 2> opposite{{{m, r, 0.3, z2}, {m, r, 0.3 + kPi, z1}}};
  for (double h : {0.0, 0.3, 1.0}) {
    const ResultantUnbalance ro = resultant_unbalance(opposite, h);
    EXPECT_NEAR(std::abs(ro.static_unbalance), 0.0, 1e-17);
    EXPECT_NEAR(std::abs(ro.couple_unbalance), m * r * d, 1e-16);
    EXPECT_NEAR(std::arg(ro.couple_unbalance), 0.3, 1e-12);  // the upper mass's direction
  }
  // Same side: U = 2 m r, no couple about the mid-height.
  const std::array<PlaneMass, 2> same{{{m, r, 0.3, z2}, {m, r, 0.3, z1}}};
  const ResultantUnbalance rs = resultant_unbalance(same, 0.5 * (z1 + z2));
  EXPECT_NEAR(std::abs(rs.static_unbalance), 2 * m * r, 1e-16);
  EXPECT_NEAR(std::abs(rs.couple_unbalance), 0.0, 1e-17);
  // ...but Eq. 2 as printed (about the origin, h = 0) reports a couple m r (z1 + z2).
  EXPECT_NEAR(std::abs(resultant_unbalance(same, 0.0).couple_unbalance), m * r * (z1 + z2), 1e-16);
  // Eq. 8's right-hand side F h + T is the same whatever reference height is chosen.
  const std::array<PlaneMass, 2> any{{{0.05, r, 0.4, z2}, {0.12, r, 2.2, z1}}};
  const double w = 8.0;
  const cd ref = unbalance_forcing(to_machine_unbalance(resultant_unbalance(any, 0.0)), w)(1);
  for (double h : {0.1, 0.325, 0.9}) {
    const Eigen::Vector2cd f = unbalance_forcing(to_machine_unbalance(resultant_unbalance(any, h)), w);
    EXPECT_NEAR(std::abs(f(1) - ref) / std::abs(ref), 0.0, 1e-13);
  }
}

// The weight on the horizontal plates (beam-column): the closed form against an independent
// shooting solution of E I w'''' + P w'' = 0 with w(0) = w'(0) = w'(L) = 0, w(L) = d (RK4), the
// small-load limit 12 E I / L^3 - 6 P / (5 L), and zero stiffness at the Euler load.
TEST(SpringPlate, ColumnUnderAxialLoadMatchesShootingAndLimits) {
  const SpringPlate plate = horizontal_plate();
  const double ei = plate.youngs_modulus * plate_second_moment(plate), L = plate.length;
  const double p_cr = guided_column_buckling_load(plate);
  EXPECT_NEAR(p_cr, kPi * kPi * ei / (L * L), 1e-9 * p_cr);
  auto shooting = [&](double load) {
    // State (w, w', w'', w'''); w'''' = -(P/EI) w''. Unknowns a = w''(0), b = w'''(0).
    auto end = [&](double a, double b) {
      std::array<double, 4> y{0, 0, a, b};
      const int n = 4000;
      const double h = L / n, q2 = load / ei;
      auto f = [&](const std::array<double, 4>& s) { return std::array<double, 4>{s[1], s[2], s[3], -q2 * s[2]}; };
      for (int i = 0; i < n; ++i) {
        auto add = [](std::array<double, 4> s, const std::array<double, 4>& d, double c) {
          for (int k = 0; k < 4; ++k) s[k] += c * d[k];
          return s;
        };
        const auto k1 = f(y), k2 = f(add(y, k1, h / 2)), k3 = f(add(y, k2, h / 2)), k4 = f(add(y, k3, h));
        for (int k = 0; k < 4; ++k) y[k] += h / 6 * (k1[k] + 2 * k2[k] + 2 * k3[k] + k4[k]);
      }
      return y;
    };
    const auto ya = end(1, 0), yb = end(0, 1);
    // w(L) = 1e-4, w'(L) = 0.
    const double d = 1e-4, det = ya[0] * yb[1] - yb[0] * ya[1];
    const double a = d * yb[1] / det, b = -d * ya[1] / det;
    (void)a;
    return std::abs(ei * b) / d;  // end shear over deflection (w'(0) = 0: no P w' term)
  };
  for (double share : {0.0, 0.1, 0.5, 0.9}) {
    const double load = share * p_cr;
    const double k = guided_column_lateral_stiffness(plate, load);
    EXPECT_NEAR(k / shooting(load), 1.0, 1e-7) << share;
  }
  const double k0 = guided_plate_stiffness(plate), small = 1e-3 * p_cr;
  EXPECT_NEAR(guided_column_lateral_stiffness(plate, 0.0), k0, 1e-12 * k0);
  EXPECT_NEAR(guided_column_lateral_stiffness(plate, small), k0 - 6 * small / (5 * L), 1e-6 * k0);
  EXPECT_NEAR(guided_column_lateral_stiffness(plate, p_cr) / k0, 0.0, 1e-9);
  EXPECT_LT(guided_column_lateral_stiffness(plate, 1.1 * p_cr), 0.0);
}

}  // namespace
}  // namespace poise::models
