// The platform's stabilization loop (models/stabilization_loop.h): gains, the derived
// closed-loop poles and crossover against independent computations, the rate-loop option,
// and RK4's order with the disturbance evaluated at its stages.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>

#include "models/stabilization_loop.h"

namespace poise::models {
namespace {

constexpr double kPi = std::numbers::pi;

StabilizationLoop pid(double j, double fn, double zeta, double rho) {
  StabilizationLoop l;
  l.inertia = j;
  l.frequency_hz = fn;
  l.damping = zeta;
  l.integral_ratio = rho;
  return l;
}

// |L(j w)| of the open loop C(s) / (J s^2), C = K_p + K_d s + K_i / s, computed directly.
double open_loop_gain(const StabilizationLoop& l, double w) {
  const std::complex<double> s(0.0, w);
  return std::abs((l.kp() + l.kd() * s + l.ki() / s) / (l.inertia * s * s));
}

// Independent crossover: bisection on log w of |L| = 1 (|L| falls through 1 once here).
double crossover_by_bisection(const StabilizationLoop& l) {
  double lo = 1.0, hi = 1e5;
  for (int i = 0; i < 200; ++i) {
    const double mid = std::sqrt(lo * hi);
    (open_loop_gain(l, mid) > 1.0 ? lo : hi) = mid;
  }
  return std::sqrt(lo * hi) / (2 * kPi);
}

// Characteristic polynomial J s^3 + K_d s^2 + K_p s + K_i evaluated at s.
std::complex<double> characteristic(const StabilizationLoop& l, std::complex<double> s) {
  return l.inertia * s * s * s + l.kd() * s * s + l.kp() * s + l.ki();
}

TEST(StabilizationLoop, PidGainsPolesAndCrossoverOfTheShippedLoop) {
  // The platform's loop: f_n = 40 Hz, zeta = 0.7, rho = 0.2 (models/platform_three_gimbal.toml).
  const StabilizationLoop l = pid(2.5e-4, 40.0, 0.7, 0.2);
  const double wn = 2 * kPi * 40.0;
  EXPECT_NEAR(l.kp(), 2.5e-4 * wn * wn, 1e-12);
  EXPECT_NEAR(l.kd(), 2 * 0.7 * 2.5e-4 * wn, 1e-15);
  EXPECT_NEAR(l.ki(), l.kp() * wn * 0.2, 1e-9);
  const auto poles = l.closed_loop_poles();
  ASSERT_EQ(poles.size(), 3u);
  for (const auto& p : poles) EXPECT_LT(std::abs(characteristic(l, p)), 1e-9 * l.ki());
  // Real pole about 12 Hz, the pair about 22 +- 24j Hz (p^3 + 1.4 p^2 + p + 0.2 = 0).
  EXPECT_NEAR(poles[0].imag(), 0.0, 1e-9);
  EXPECT_NEAR(-poles[0].real() / (2 * kPi), 12.0, 0.2);
  EXPECT_NEAR(-poles[1].real() / (2 * kPi), 22.0, 0.3);
  EXPECT_NEAR(std::abs(poles[1].imag()) / (2 * kPi), 24.2, 0.3);
  // Crossover: polynomial root against bisection; 59 Hz, not 40 Hz.
  EXPECT_NEAR(l.crossover_hz(), crossover_by_bisection(l), 1e-6);
  EXPECT_NEAR(l.crossover_hz(), 59.0, 0.3);
  EXPECT_NEAR(open_loop_gain(l, 2 * kPi * l.crossover_hz()), 1.0, 1e-9);
  // Least disturbance stiffness 0.81 J w_n^2 near w_n / 2 (not at w_n): against a fine scan.
  const auto [k_min, f_min] = l.least_disturbance_stiffness();
  double scan = INFINITY;
  for (double f = 1.0; f < 400.0; f += 0.001) scan = std::min(scan, l.disturbance_stiffness(2 * kPi * f));
  EXPECT_NEAR(k_min, scan, 1e-6 * scan);
  EXPECT_NEAR(k_min / (l.inertia * wn * wn), 0.81, 0.01);
  EXPECT_GT(f_min, 15.0);
  EXPECT_LT(f_min, 25.0);
}

TEST(StabilizationLoop, RateLoopHasATrueCrossoverAndNoPositionIntegral) {
  StabilizationLoop l = pid(1e-3, 40.0, 0.7, 0.25);
  l.type = LoopType::kRatePi;
  EXPECT_EQ(l.ki(), 0.0);
  EXPECT_NEAR(l.crossover_hz(), 40.0, 1e-9);
  EXPECT_NEAR(crossover_by_bisection(l), 40.0, 1e-6);
  // DC stiffness K_v w_i = J w_c^2 rho / sqrt(1 + rho^2): finite.
  const double wc = 2 * kPi * 40.0;
  EXPECT_NEAR(l.disturbance_stiffness(0.0), 1e-3 * wc * wc * 0.25 / std::sqrt(1 + 0.0625), 1e-9);
  const auto poles = l.closed_loop_poles();
  ASSERT_EQ(poles.size(), 2u);
  for (const auto& p : poles) EXPECT_LT(std::abs(l.inertia * p * p + l.kd() * p + l.kp()), 1e-9 * l.kp());
  // A held torque leaves a held error T / K_p (no integrator), the PID takes it out.
  const auto step = [](double t) { return t > 0 ? 1e-3 : 0.0; };
  const auto th = loop_response(l, step, 1e-4, 20001);
  EXPECT_NEAR(th.back(), 1e-3 / l.kp(), 1e-6 * 1e-3 / l.kp());
  // From the steady state under a torque present at t = 0: the held error from the start.
  const auto th0 = loop_response(l, [](double) { return 2e-3; }, 1e-4, 11);
  EXPECT_NEAR(th0[0], 2e-3 / l.kp(), 1e-15);
  EXPECT_NEAR(th0[10], 2e-3 / l.kp(), 1e-12);
}

TEST(StabilizationLoop, StepAndSineResponses) {
  const StabilizationLoop l = pid(2e-3, 20.0, 0.7, 0.1);
  EXPECT_TRUE(std::isinf(l.disturbance_stiffness(0.0)));
  const double w_hi = 2 * kPi * 2000.0;
  EXPECT_NEAR(l.disturbance_stiffness(w_hi) / (l.inertia * w_hi * w_hi), 1.0, 0.02);
  // A torque step: peak error about T / K_p, then the integrator brings it back to 0.
  const auto th = loop_response(l, [](double t) { return t > 0 ? 1e-3 : 0.0; }, 1e-4, 30001);
  double peak = 0;
  for (double v : th) peak = std::max(peak, std::abs(v));
  EXPECT_GT(peak, 0.5e-3 / l.kp());
  EXPECT_LT(peak, 2.0e-3 / l.kp());
  EXPECT_LT(std::abs(th.back()), 0.01 * peak);
}

// Exact response of J th'' + K_d th' + K_p th + K_i int th = T0 sin(w t) from rest (all
// three states 0, T(0) = 0): the steady sinusoid plus the homogeneous part fitted to the
// initial conditions, in the state z = int th: J z''' + K_d z'' + K_p z' + K_i z = T0 sin(w t).
double exact_sine_response(const StabilizationLoop& l, double t0, double w, double t) {
  const std::complex<double> jw(0.0, w);
  // Particular solution z_p = Im(Z e^{i w t}), Z = T0 / P(j w).
  const std::complex<double> z = t0 / characteristic(l, jw);
  const auto poles = l.closed_loop_poles();
  // z(0) = z'(0) = z''(0) = 0: sum_k c_k p_k^n = -z_p^(n)(0), n = 0, 1, 2.
  Eigen::Matrix3cd a;
  Eigen::Vector3cd b;
  for (int n = 0; n < 3; ++n) {
    for (int k = 0; k < 3; ++k) a(n, k) = std::pow(poles[static_cast<std::size_t>(k)], n);
    b(n) = -(std::pow(jw, n) * z).imag();
  }
  const Eigen::Vector3cd c = a.fullPivLu().solve(b);
  // th = z'.
  std::complex<double> th = (jw * z * std::exp(jw * t)).imag();
  for (int k = 0; k < 3; ++k) th += c(k) * poles[static_cast<std::size_t>(k)] * std::exp(poles[static_cast<std::size_t>(k)] * t);
  return th.real();
}

TEST(StabilizationLoop, Rk4WithTheDisturbanceAtItsStagesIsOfOrderFour) {
  const StabilizationLoop l = pid(2e-3, 20.0, 0.7, 0.2);
  const double w = 2 * kPi * 55.0, t_end = 0.2;
  const auto torque = [w](double t) { return 1e-3 * std::sin(w * t); };
  std::vector<double> err;
  for (double dt : {1e-3, 5e-4, 2.5e-4}) {
    const auto n = static_cast<std::size_t>(std::llround(t_end / dt)) + 1;
    const auto th = loop_response(l, torque, dt, n);
    double e = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      e = std::max(e, std::abs(th[k] - exact_sine_response(l, 1e-3, w, static_cast<double>(k) * dt)));
    }
    err.push_back(e);
  }
  // Halving dt divides the error by 2^4 = 16 (a torque interpolated linearly between the
  // samples would give order 2: a ratio of 4).
  EXPECT_NEAR(std::log2(err[0] / err[1]), 4.0, 0.3);
  EXPECT_NEAR(std::log2(err[1] / err[2]), 4.0, 0.3);
  EXPECT_LT(err[2], 1e-6 * 1e-3 / l.kp());
}

}  // namespace
}  // namespace poise::models
