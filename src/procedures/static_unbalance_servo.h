#pragma once
// The servo of the static-unbalance procedure as the integrator and the acquisition share it
// (static_unbalance_procedure.cc, static_unbalance_servo.cc; internal to procedures/): the
// per-position context, the state layout, the reference motion and the commanded current.
// The equations are stated in static_unbalance_procedure.h.
#include <cmath>

#include "models/disk_rotor.h"
#include "procedures/static_unbalance_procedure.h"

namespace poise::procedures {

struct StaticUnbalanceWorkspace::Context {
  models::DiskRotorParams disk;
  models::GimbalGravity gravity;
  double kp = 0, kd = 0, ki = 0, j_ff = 0, kt_nominal = 1, kt_true = 1, i_max = 1;
  double disturbance_torque = 0;  // constant external torque at this position (N m)
  double t0 = 0, omega = 1, amplitude = 0, rate_amplitude = 0, centre = 0;
  double t1 = 0;  // start of the integration window (s)
  long rhs_calls = 0;
};

namespace servo {
using Context = StaticUnbalanceWorkspace::Context;
// States. Dynamic supports: phi, phidot, y, ydot, z, zdot, integral of the angle error;
// quasi-static: phi, phidot, integral of the angle error. Then, both, three window integrals:
// current, squared tracking error, clipped excess of the commanded current.
constexpr int kDynamicStates = 10, kQuasiStates = 6, kQuadratures = 3;

struct Reference {
  double phi, rate, acc;
};

// phi_ref = phi_c - a cos(w (t - t0)) after t0 (so phidot_ref = A sin(...)), held before.
inline Reference reference(const Context& c, double t) {
  if (t < c.t0) return {c.centre - c.amplitude, 0.0, 0.0};
  const double w = c.omega * (t - c.t0);
  return {c.centre - c.amplitude * std::cos(w), c.rate_amplitude * std::sin(w),
          c.rate_amplitude * c.omega * std::cos(w)};
}

// Commanded amplifier current: PID plus acceleration feed-forward (before the limit).
inline double commanded_current(const Context& c, const Reference& r, double phi, double phidot, double integral) {
  return (c.kp * (r.phi - phi) + c.kd * (r.rate - phidot) + c.ki * integral + c.j_ff * r.acc) / c.kt_nominal;
}

}  // namespace servo
}  // namespace poise::procedures
