#pragma once
/// The counterweight of Eq. 23 (Yang 2015) as placed on the rig, and the unbalance it leaves.
///
/// Frames. The counterweight holes and the test loads are referenced to the disk's geometric
/// centre O; the rotor turns about the bearing axis O', and bearing run-out puts O at r from
/// O' (a vector fixed in the disk). A mass m_i at p_i from O sits at p_i + r from O'.
/// Gravity's torque about the axis the rotor turns on is g x its first moment about O':
///     S' = sum m_i (p_i + r) = U_O + M r,
/// with U_O the first moment about O and M the mass. The test measures S' (the motor holds
/// m g |e + r|, disk_rotor.h). After a counterweight m_c at p_c (from O) the rotor holds
///     R = U_O + M r + m_c (p_c + r) = S' + m_c p_c + m_c r,                       (1)
/// the residual the balance leaves about the bearing axis: the run-out acts on the
/// counterweight's mass too. Taken about O instead (U_O + m_c p_c) it leaves out
/// (M + m_c) r, 3 g*mm for a 1.5 kg rotor on a 2 um run-out.
///
/// Placement angle (Sec. 5.2). The fitted phase is b = eps + z + tz: eps the unbalance's
/// angle on the disk, z the gimbal's zero error (it oscillates about z), tz the turntable's
/// zero error (sin(theta + tz + z + eps) is what the motor holds). Placed on the disk's own
/// angle scale at b + pi, the counterweight lands off by z + tz. Turned back on the turntable
/// to the fitted angle and set against gravity, it lands at the unbalance's true direction
/// + pi, up to the turntable's positioning error at that one position: z and tz cancel.
#include <array>
#include <cmath>
#include <string>

namespace poise::kinds::gimbal_static_unbalance {

/// Disk-frame angle of the counterweight (rad): `placement` "disk_frame" or "turntable",
/// `fitted_phase` b, `zero_errors` z + tz (rad), `placement_error` the angle error of setting
/// it (counterweight_angle, plus the turntable's positioning error when turned back).
inline double counterweight_disk_angle(const std::string& placement, double fitted_phase, double zero_errors,
                                       double placement_error) {
  const double pi = 3.141592653589793;
  return placement == "turntable" ? fitted_phase - zero_errors + pi + placement_error
                                  : fitted_phase + pi + placement_error;
}

/// Eq. (1): residual first moment about the bearing axis (kg m, disk frame) after a
/// counterweight of mass `m_c` at radius `r_c` and disk angle `a_c`, for a rotor whose first
/// moment about the bearing axis is `s_bearing` (U_O + M r) and a run-out `runout` (m).
inline std::array<double, 2> residual_about_bearing_axis(const std::array<double, 2>& s_bearing,
                                                         const std::array<double, 2>& runout, double m_c, double r_c,
                                                         double a_c) {
  return {s_bearing[0] + m_c * (r_c * std::cos(a_c) + runout[0]),
          s_bearing[1] + m_c * (r_c * std::sin(a_c) + runout[1])};
}

}  // namespace poise::kinds::gimbal_static_unbalance
