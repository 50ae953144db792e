#include "models/stabilization_loop.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unsupported/Eigen/Polynomials>

namespace poise::models {

namespace {
double omega(const StabilizationLoop& l) { return 2.0 * std::numbers::pi * l.frequency_hz; }
// Rate PI: K_v = J w_c / sqrt(1 + rho^2) puts |L(j w_c)| = 1.
double rate_gain(const StabilizationLoop& l) {
  return l.inertia * omega(l) / std::sqrt(1.0 + l.integral_ratio * l.integral_ratio);
}

// Roots of c[0] x^n + c[1] x^(n-1) + ... + c[n] (c[0] != 0), by Eigen's polynomial solver.
std::vector<std::complex<double>> roots(const std::vector<double>& c) {
  Eigen::VectorXd ascending(static_cast<Eigen::Index>(c.size()));
  for (std::size_t k = 0; k < c.size(); ++k) ascending(static_cast<Eigen::Index>(c.size() - 1 - k)) = c[k];
  Eigen::PolynomialSolver<double, Eigen::Dynamic> solver(ascending);
  const auto& r = solver.roots();
  return std::vector<std::complex<double>>(r.data(), r.data() + r.size());
}
}  // namespace

const char* loop_type_name(LoopType t) { return t == LoopType::kRatePi ? "rate_pi" : "position_pid"; }

double StabilizationLoop::kp() const {
  if (type == LoopType::kRatePi) return rate_gain(*this) * integral_ratio * omega(*this);
  return inertia * omega(*this) * omega(*this);
}
double StabilizationLoop::kd() const {
  if (type == LoopType::kRatePi) return rate_gain(*this);
  return 2.0 * damping * inertia * omega(*this);
}
double StabilizationLoop::ki() const {
  if (type == LoopType::kRatePi) return 0.0;
  return kp() * omega(*this) * integral_ratio;
}

double StabilizationLoop::disturbance_stiffness(double w) const {
  if (w == 0.0) return ki() > 0 ? std::numeric_limits<double>::infinity() : kp();
  return std::abs(std::complex<double>(kp() - inertia * w * w, kd() * w - ki() / w));
}

std::vector<std::complex<double>> StabilizationLoop::closed_loop_poles() const {
  std::vector<std::complex<double>> r = ki() > 0 ? roots({inertia, kd(), kp(), ki()}) : roots({inertia, kd(), kp()});
  std::sort(r.begin(), r.end(), [](auto a, auto b) {
    return std::abs(a.imag()) != std::abs(b.imag()) ? std::abs(a.imag()) < std::abs(b.imag()) : a.real() > b.real();
  });
  return r;
}

double StabilizationLoop::crossover_hz() const {
  // |C(jw)|^2 = J^2 w^4 with C = K_p + j (K_d w - K_i / w); times w^2, in x = w^2:
  //   J^2 x^3 - K_d^2 x^2 - (K_p^2 - 2 K_d K_i) x - K_i^2 = 0.
  const double j = inertia, p = kp(), d = kd(), i = ki();
  double best = 0.0;
  for (const auto& x : roots({j * j, -d * d, -(p * p - 2.0 * d * i), -i * i})) {
    if (std::abs(x.imag()) <= 1e-9 * std::abs(x) && x.real() > 0) best = std::max(best, x.real());
  }
  return std::sqrt(best) / (2.0 * std::numbers::pi);
}

std::pair<double, double> StabilizationLoop::least_disturbance_stiffness() const {
  // Coarse log grid from w / 1000 to 100 w, then golden-section refinement around the least.
  const double w0 = omega(*this) * 1e-3;
  const int n = 2001;
  const double step = std::log(1e5) / (n - 1);
  int best = 0;
  double best_k = std::numeric_limits<double>::infinity();
  for (int k = 0; k < n; ++k) {
    const double v = disturbance_stiffness(w0 * std::exp(step * k));
    if (v < best_k) best_k = v, best = k;
  }
  double a = std::log(w0) + step * std::max(best - 1, 0), b = std::log(w0) + step * std::min(best + 1, n - 1);
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int it = 0; it < 100; ++it) {
    const double c = b - g * (b - a), e = a + g * (b - a);
    if (disturbance_stiffness(std::exp(c)) < disturbance_stiffness(std::exp(e))) {
      b = e;
    } else {
      a = c;
    }
  }
  const double w = std::exp(0.5 * (a + b));
  return {disturbance_stiffness(w), w / (2.0 * std::numbers::pi)};
}

Eigen::Vector3d CarrierProfile::acceleration(double t) const {
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  if (t >= onset) a += manoeuvre * (rise_time > 0 ? std::min(1.0, (t - onset) / rise_time) : 1.0);
  for (const auto& v : vibration) a += v.amplitude * std::sin(2.0 * std::numbers::pi * v.frequency_hz * t);
  return a;
}

std::size_t CarrierProfile::steps() const {
  return static_cast<std::size_t>(std::floor(duration / time_step + 1e-9)) + 1;
}

std::vector<double> loop_response(const StabilizationLoop& loop, const std::function<double(double)>& torque, double dt,
                                  std::size_t steps) {
  std::vector<double> out(steps, 0.0);
  if (steps == 0) return out;
  const double j = loop.inertia, kp = loop.kp(), kd = loop.kd(), ki = loop.ki();
  // State (th, th', int th), from the steady state under T(0): with the integrator th = 0 and
  // the integral holding T(0); without it (rate loop) the held error T(0) / K_p.
  const double t0 = torque(0.0);
  double th = ki > 0 ? 0.0 : t0 / kp, w = 0.0, in = ki > 0 ? t0 / ki : 0.0;
  out[0] = th;
  auto deriv = [&](double a, double b, double c, double u, double* d) {
    d[0] = b;
    d[1] = (u - kp * a - kd * b - ki * c) / j;
    d[2] = a;
  };
  for (std::size_t k = 0; k + 1 < steps; ++k) {
    const double t = static_cast<double>(k) * dt;
    // The disturbance where RK4 asks for it: the stages at t, t + dt/2 (twice) and t + dt.
    const double u0 = torque(t), um = torque(t + 0.5 * dt), u1 = torque(t + dt);
    double k1[3], k2[3], k3[3], k4[3];
    deriv(th, w, in, u0, k1);
    deriv(th + 0.5 * dt * k1[0], w + 0.5 * dt * k1[1], in + 0.5 * dt * k1[2], um, k2);
    deriv(th + 0.5 * dt * k2[0], w + 0.5 * dt * k2[1], in + 0.5 * dt * k2[2], um, k3);
    deriv(th + dt * k3[0], w + dt * k3[1], in + dt * k3[2], u1, k4);
    th += dt / 6.0 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0]);
    w += dt / 6.0 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1]);
    in += dt / 6.0 * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2]);
    out[k + 1] = th;
  }
  return out;
}

}  // namespace poise::models
