#include "models/stabilization_loop.h"

#include <cmath>
#include <complex>
#include <limits>
#include <numbers>

namespace poise::models {

namespace {
double omega_c(const StabilizationLoop& l) { return 2.0 * std::numbers::pi * l.bandwidth_hz; }
}  // namespace

double StabilizationLoop::kp() const { return inertia * omega_c(*this) * omega_c(*this); }
double StabilizationLoop::kd() const { return 2.0 * damping * inertia * omega_c(*this); }
double StabilizationLoop::ki() const { return kp() * omega_c(*this) * integral_ratio; }

double StabilizationLoop::disturbance_stiffness(double w) const {
  if (w == 0.0) return ki() > 0 ? std::numeric_limits<double>::infinity() : kp();
  return std::abs(std::complex<double>(kp() - inertia * w * w, kd() * w - ki() / w));
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

std::vector<double> loop_response(const StabilizationLoop& loop, const std::vector<double>& torque, double dt) {
  std::vector<double> out(torque.size(), 0.0);
  if (torque.empty()) return out;
  const double j = loop.inertia, kp = loop.kp(), kd = loop.kd(), ki = loop.ki();
  // State (th, th', int th); the integrator starts holding the initial torque: the
  // steady state under it, so only changes of T move th. Input dT = T - T(0).
  const double t0 = torque[0];
  double th = 0.0, w = 0.0, in = 0.0;
  auto deriv = [&](double a, double b, double c, double dtorque, double* d) {
    d[0] = b;
    d[1] = (dtorque - kp * a - kd * b - ki * c) / j;
    d[2] = a;
  };
  for (std::size_t k = 0; k + 1 < torque.size(); ++k) {
    const double u0 = torque[k] - t0, u1 = torque[k + 1] - t0, um = 0.5 * (u0 + u1);
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
