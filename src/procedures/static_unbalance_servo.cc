// The servo's right-hand sides (dynamic and quasi-static supports), their tolerances, and the
// workspace that keeps one CVODE integrator per formulation (static_unbalance_servo.h).
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "procedures/static_unbalance_servo.h"

namespace poise::procedures {
namespace {
using namespace servo;

// The servo integral and the window integrals of both formulations (q: their first index).
inline void servo_and_window(const Context& c, double t, const Reference& r, double phi, double cmd, double i,
                             double* servo_dot, double* q_dot) {
  // Conditional integration: the integrator holds while the amplifier saturates.
  *servo_dot = i != cmd ? 0.0 : r.phi - phi;
  const bool in_window = t >= c.t1;
  const double e = r.phi - phi;
  q_dot[0] = in_window ? i : 0.0;
  q_dot[1] = in_window ? e * e : 0.0;
  q_dot[2] = in_window ? std::max(std::abs(cmd) - c.i_max, 0.0) : 0.0;
}

int rhs_dynamic(double t, const double* y, double* ydot, void* user) {
  auto* c = static_cast<Context*>(user);
  ++c->rhs_calls;
  const Reference r = reference(*c, t);
  const double cmd = commanded_current(*c, r, y[0], y[1], y[6]);
  const double i = std::clamp(cmd, -c->i_max, c->i_max);
  const models::DiskState s{y[0], y[1], y[2], y[3], y[4], y[5]};
  const auto acc = models::disk_accelerations(c->disk, c->gravity, s, c->kt_true * i + c->disturbance_torque);
  ydot[0] = y[1];
  ydot[1] = acc[0];
  ydot[2] = y[3];
  ydot[3] = acc[1];
  ydot[4] = y[5];
  ydot[5] = acc[2];
  servo_and_window(*c, t, r, y[0], cmd, i, &ydot[6], &ydot[7]);
  for (int k = 0; k < kDynamicStates; ++k) {
    if (!std::isfinite(ydot[k])) return 1;  // recoverable: CVODE retries a smaller step
  }
  return 0;
}

int rhs_quasi_static(double t, const double* y, double* ydot, void* user) {
  auto* c = static_cast<Context*>(user);
  ++c->rhs_calls;
  const Reference r = reference(*c, t);
  const double cmd = commanded_current(*c, r, y[0], y[1], y[2]);
  const double i = std::clamp(cmd, -c->i_max, c->i_max);
  ydot[0] = y[1];
  ydot[1] = models::rigid_axis_acceleration(c->disk, c->gravity, y[0], y[1], c->kt_true * i + c->disturbance_torque);
  servo_and_window(*c, t, r, y[0], cmd, i, &ydot[2], &ydot[3]);
  for (int k = 0; k < kQuasiStates; ++k) {
    if (!std::isfinite(ydot[k])) return 1;
  }
  return 0;
}

// Absolute tolerances: the model's per-state ones for the mechanical states (7, the dynamic
// order), then the window integrals: the current's tight enough that its mean is good to
// 1e-3 rtol of the current limit; the tracking and excess integrals are diagnostics, left
// out of the error test (a huge tolerance).
solvers::CvodeOptions extended_options(solvers::CvodeOptions opt, Supports supports, double i_scale) {
  std::vector<double> mech = opt.atol_per_state;
  if (mech.size() != 7) mech.assign(7, opt.atol);
  std::vector<double> a;
  if (supports == Supports::kDynamic) {
    a = mech;
  } else {
    a = {mech[0], mech[1], mech[6]};
  }
  a.push_back(1e-3 * opt.rtol * i_scale);  // A s
  a.push_back(1e30);
  a.push_back(1e30);
  opt.atol_per_state = a;
  return opt;
}

}  // namespace

StaticUnbalanceWorkspace::StaticUnbalanceWorkspace(solvers::CvodeOptions opt)
    : opt_(std::move(opt)), ctx_(std::make_unique<Context>()) {}

StaticUnbalanceWorkspace::~StaticUnbalanceWorkspace() = default;

solvers::CvodeIntegrator& StaticUnbalanceWorkspace::integrator(Supports supports) {
  // The current's tolerance scale: 1 A (the window integrals are in A s); CvodeOptions are
  // the model's, fixed for the workspace's life.
  if (supports == Supports::kDynamic) {
    if (dynamic_ == nullptr) {
      dynamic_ = std::make_unique<solvers::CvodeIntegrator>(kDynamicStates, rhs_dynamic, ctx_.get(),
                                                            extended_options(opt_, supports, 1.0));
    }
    return *dynamic_;
  }
  if (quasi_static_ == nullptr) {
    quasi_static_ = std::make_unique<solvers::CvodeIntegrator>(kQuasiStates, rhs_quasi_static, ctx_.get(),
                                                               extended_options(opt_, supports, 1.0));
  }
  return *quasi_static_;
}

}  // namespace poise::procedures
