#pragma once
/// How a disturbance torque on a gimbal axis becomes a pointing error: the axis' stabilization
/// loop, stated here as a PID position loop on the axis inertia (the loop of the test servo,
/// procedures/static_unbalance_procedure.h, with the platform's own gains),
///   J th'' = T(t) - (K_p th + K_d th' + K_i int th),
///   K_p = J w_c^2,  K_d = 2 zeta J w_c,  K_i = K_p w_c rho,   w_c = 2 pi f_c,
/// with th the axis' angle error against its command. Its disturbance stiffness
///   |T / th|(w) = |K_p - J w^2 + j (K_d w - K_i / w)|   (N m/rad)
/// is infinite at DC (the integrator takes out a constant torque, gravity's included),
/// least near w_c. The loop is integrated with classical RK4 on the profile's time step,
/// the torque interpolated linearly; exact for the linear ODE to O(dt^4).
///
/// Carrier acceleration profile (base frame): a manoeuvre a_m ramped linearly from t_on over
/// t_rise and held, plus sinusoidal vibration a_k sin(2 pi f_k t).
#include <Eigen/Dense>
#include <vector>

namespace poise::models {

struct StabilizationLoop {
  double inertia = 0.0;        ///< J about the axis (kg m^2)
  double bandwidth_hz = 20.0;  ///< f_c
  double damping = 0.7;        ///< zeta
  double integral_ratio = 0.1; ///< rho
  double kp() const;
  double kd() const;
  double ki() const;
  /// |T / th| at angular frequency w (rad/s); w = 0 gives +infinity with an integrator.
  double disturbance_stiffness(double w) const;
};

struct VibrationLine {
  Eigen::Vector3d amplitude = Eigen::Vector3d::Zero();  ///< m/s^2 (base frame)
  double frequency_hz = 0.0;
};

struct CarrierProfile {
  double duration = 1.0;   ///< s
  double time_step = 1e-3; ///< s
  Eigen::Vector3d manoeuvre = Eigen::Vector3d::Zero();  ///< m/s^2 (base frame), held after the ramp
  double onset = 0.0;      ///< s
  double rise_time = 0.0;  ///< s (0 = a step)
  std::vector<VibrationLine> vibration;
  Eigen::Vector3d acceleration(double t) const;
  std::size_t steps() const;  ///< samples 0..steps()-1 at t = k dt
};

/// Angle error th(t_k) (rad) of the loop under torque samples T(t_k) (N m) at step dt, from
/// rest (th = 0, integrator holding T(0)).
std::vector<double> loop_response(const StabilizationLoop& loop, const std::vector<double>& torque, double dt);

}  // namespace poise::models
