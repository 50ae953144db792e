#pragma once
/// How a disturbance torque on a gimbal axis becomes a pointing error: the axis' stabilization
/// loop on the axis inertia J, th the axis' angle error against its command and T(t) the
/// disturbance torque. Two loop types (model key [stabilization] loop):
///
///   * "position_pid" (the loop of the test servo, procedures/static_unbalance_procedure.h,
///     with the platform's own gains): a PID position loop
///       J th'' = T(t) - (K_p th + K_d th' + K_i int th),
///       K_p = J w_n^2,  K_d = 2 zeta J w_n,  K_i = K_p w_n rho,   w_n = 2 pi f_n,
///     where f_n (key natural_frequency) is the natural frequency of the PD part, NOT the loop's
///     bandwidth. The closed-loop poles are the roots of J s^3 + K_d s^2 + K_p s + K_i, in
///     units of w_n those of p^3 + 2 zeta p^2 + p + rho: for zeta = 0.7, rho = 0.2 one real pole
///     at 0.30 w_n and a pair at (-0.55 +- 0.61 j) w_n (12 Hz and 22 +- 24j Hz at f_n = 40 Hz);
///     the open loop L = (K_d s^2 + K_p s + K_i) / (J s^3) crosses |L| = 1 at 1.47 w_n
///     (59 Hz at 40 Hz: x = (w / w_n)^2 solves x^3 - 4 zeta^2 x^2 - (1 - 4 zeta rho) x - rho^2 = 0).
///     Computed by closed_loop_poles() and crossover_hz(), tested against an independent
///     bisection in tests/models/stabilization_loop_test.cc.
///   * "rate_pi": a PI loop on the rate th' with a true open-loop crossover f_c (key crossover):
///       J th'' = T(t) - K_v (th' + w_i th),  w_i = rho w_c,  K_v = J w_c / sqrt(1 + rho^2),
///     so that |L(j w_c)| = |K_v (1 + w_i / (j w_c)) / (j w_c J)| = 1 exactly. It is the same
///     equation as the PID with K_p = K_v w_i, K_d = K_v, K_i = 0: no integral of the angle, so
///     a held torque leaves a held error T / (K_v w_i) (a rate loop does not hold position).
///
/// Disturbance stiffness (either type)
///   |T / th|(w) = |K_p - J w^2 + j (K_d w - K_i / w)|   (N m/rad),
/// infinite at DC with the position integrator (it takes out a constant torque, gravity's
/// included), K_v w_i for the rate loop. Its least value: for the PID with zeta = 0.7,
/// rho = 0.2 it is 0.81 J w_n^2 at about w_n / 2 (least_disturbance_stiffness() finds it by
/// a golden-section search on a log-frequency grid), not at w_n.
///
/// The loop is integrated with classical RK4; the disturbance is evaluated where RK4 asks for
/// it (t, t + dt/2 twice, t + dt), so the global error is O(dt^4) for a smooth disturbance
/// (tested against the closed-form response to a sinusoid, observed order 4).
///
/// Carrier acceleration profile (base frame): a manoeuvre a_m ramped linearly from t_on over
/// t_rise and held, plus sinusoidal vibration a_k sin(2 pi f_k t).
#include <Eigen/Dense>
#include <complex>
#include <functional>
#include <string>
#include <vector>

namespace poise::models {

enum class LoopType { kPositionPid, kRatePi };

/// "position_pid" or "rate_pi".
const char* loop_type_name(LoopType t);

struct StabilizationLoop {
  LoopType type = LoopType::kPositionPid;
  double inertia = 0.0;  ///< J about the axis (kg m^2)
  /// position_pid: f_n, natural frequency of the PD part (Hz); rate_pi: f_c, the open-loop
  /// crossover (Hz).
  double frequency_hz = 20.0;
  double damping = 0.7;         ///< zeta (position_pid only)
  double integral_ratio = 0.1;  ///< rho
  double kp() const;            ///< N m/rad
  double kd() const;            ///< N m s/rad
  double ki() const;            ///< N m/(rad s)
  /// |T / th| at angular frequency w (rad/s); w = 0 gives +infinity with an integrator.
  double disturbance_stiffness(double w) const;
  /// Roots of the closed-loop characteristic polynomial (rad/s), sorted by |imag| then real.
  std::vector<std::complex<double>> closed_loop_poles() const;
  /// Open-loop crossover |L(j w)| = 1 (Hz): the greatest positive root.
  double crossover_hz() const;
  /// Least disturbance stiffness over frequency (N m/rad) and where (Hz).
  std::pair<double, double> least_disturbance_stiffness() const;
};

struct VibrationLine {
  Eigen::Vector3d amplitude = Eigen::Vector3d::Zero();  ///< m/s^2 (base frame)
  double frequency_hz = 0.0;
};

struct CarrierProfile {
  double duration = 1.0;                                ///< s
  double time_step = 1e-3;                              ///< s
  Eigen::Vector3d manoeuvre = Eigen::Vector3d::Zero();  ///< m/s^2 (base frame), held after the ramp
  double onset = 0.0;                                   ///< s
  double rise_time = 0.0;                               ///< s (0 = a step)
  std::vector<VibrationLine> vibration;
  Eigen::Vector3d acceleration(double t) const;
  std::size_t steps() const;  ///< samples 0..steps()-1 at t = k dt
};

/// Angle error th(t_k) (rad), t_k = k dt for k = 0..steps-1, of the loop under the torque
/// T(t) (N m), evaluated at RK4's stages, from rest (th = 0, integrator holding T(0)).
std::vector<double> loop_response(const StabilizationLoop& loop, const std::function<double(double)>& torque, double dt,
                                  std::size_t steps);

}  // namespace poise::models
