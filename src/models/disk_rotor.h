#pragma once
/// Gimbal axis under test as a disk rotor on elastic supports (Yang et al. 2015, Sec. 3,
/// Eqs. 13-18; docs/papers.md), derived anew; the printed equations have slips.
///
/// Coordinates: phi, the disk's rotation about the gimbal axis x; y, z, the translation of
/// the disk's geometric centre O from the bearing centre O' (support bending). The mass
/// centre C sits at eccentricity e from the rotation centre at angle eps in the disk frame,
/// so with p = phi + eps:  r_C = (y + e cos p, z + e sin p).
/// Gravity in the gimbal frame (g_y, g_z) comes from the turntable angle theta (and a tilt
/// of the gimbal axis against the turntable axis, gravity_in_gimbal()). Convention: at
/// theta = 0 gravity lies along +y, so (g_y, g_z) = g (cos theta, -sin theta) without tilt
/// and the torque needed to hold the disk is m g e sin(theta + p): the fitted phase b of
/// Eq. 22 estimates eps directly.
///
/// Lagrangian, with J the moment of inertia about the mass centre C:
///   T = 1/2 m (ydot^2 + zdot^2 + e^2 phidot^2 + 2 e phidot (zdot cos p - ydot sin p))
///       + 1/2 J phidot^2
///   V = 1/2 k (y^2 + z^2) + 1/2 k_CR (phi - phi_0)^2 - m (g_y (y + e cos p) + g_z (z + e sin p))
/// Non-conservative: motor torque M, viscous K_f phidot, Coulomb T_c tanh(phidot / w_s) on phi;
/// support damping c ydot, c zdot. Motor cogging -T_cog sin(N phi + psi), or a map of such
/// orders (conservative, off unless set) joins M. Lagrange's equations give
///   (J + m e^2) phi'' - m e sin p y'' + m e cos p z'' = M - K_f phi' - T_c tanh(phi'/w_s)
///                                 - k_CR (phi - phi_0) + m e (-g_y sin p + g_z cos p)
///   m y'' - m e sin p phi'' = m e cos p phi'^2 - k y - c y' + m g_y
///   m z'' + m e cos p phi'' = m e sin p phi'^2 - k z - c z' + m g_z
/// Eliminating y'', z'' (exact, no approximation):
///   J phi'' = Q_phi + e (sin p F_y - cos p F_z),   y'' = (F_y + m e sin p phi'') / m,
///   z'' = (F_z - m e cos p phi'') / m,
/// with F_y, F_z the right-hand sides of the y, z equations and Q_phi that of the phi one.
///
/// Corrections to the printed equations (each checked in tests/solvers/disk_rotor_test.cc):
///   * Eq. 13 counts m e^2 phidot^2 twice (once in the translation of C, once in
///     "J + m e^2"), hence the printed (J + 2 m e^2): with J about C it is J + m e^2.
///   * Eq. 17 carries m e (ydot sin phi - zdot cos phi) (velocities) where Lagrange gives
///     accelerations, m e (y'' sin p - z'' cos p); the velocity terms cancel exactly.
///   * Eq. 14 writes the virtual work with phi and y, z instead of their variations, and
///     with k_CR phi^2/2 mixed in; Eq. 15 is right for gravity along -z.
///   * Eq. 18's m e |oo'| sin(psi - phi) has units of kg m^2, not N m. Bearing run-out
///     (the rotation centre offset from the disk's geometric centre by a vector fixed in
///     the disk) adds to the eccentricity: the motor holds m g |e + r| sin(...), so the test
///     measures the unbalance about the bearing axis, biased by m g r against the disk's
///     geometric centre, where the counterweight holes are referenced.
/// Checks: energy T + V conserved with motor, friction and damping off; small-oscillation
/// frequencies against the eigenvalues of the linearization; holding torque
/// m g e sin(theta + p) at rest.
///
/// Quasi-static supports (rigid_axis_acceleration; model key [rotor] supports =
/// "quasi_static"). Q_phi contains no y or z: the supports act on phi only through the
/// accelerations y'', z'' in the phi equation. With the support mode far above the motion
/// (omega_s = sqrt(k/m) >> the servo bandwidth and the oscillation), y and z follow their
/// quasi-static load, k y = m g_y + m e (cos p phi'^2 + sin p phi''), whose y'' is of order
/// (omega / omega_s)^2 of the terms kept. Setting y'' = z'' = 0 in the phi equation:
///   (J + m e^2) phi'' = Q_phi,
/// the rigid rotor about the fixed bearing axis (J + m e^2 its inertia about that axis, by
/// the parallel-axis theorem). The coupling dropped, m e (-sin p y'' + cos p z''), is of
/// relative order (m e^2 / J) (omega / omega_s)^2, below 1e-9 for the Yang 2015 rig (411 Hz
/// supports, 20 Hz servo); the supports' own transients (started from the static
/// deflection, so excited only through that coupling) go with it, and with them the
/// 7-state model's stiff 411 Hz mode, so the solver steps with the motion. Checked against
/// the full model in tests/model_files/disk_rotor_quasi_static_test.cc (36-point torque estimate).
#include <array>
#include <vector>

namespace poise::models {

struct DiskRotorParams {
  double mass = 0.0;                ///< m (kg), whole rotating gimbal
  double inertia = 0.0;             ///< J about the mass centre (kg m^2)
  double eccentricity = 0.0;        ///< e (m), mass centre from the rotation centre
  double eccentricity_angle = 0.0;  ///< eps (rad), in the disk frame
  double support_stiffness = 0.0;   ///< k (N/m), bending of the supports
  double support_damping = 0.0;     ///< c (N s/m)
  double viscous_friction = 0.0;    ///< K_f (N m s/rad)
  double coulomb_friction = 0.0;    ///< T_c (N m)
  double coulomb_smoothing = 1e-3;  ///< w_s (rad/s), tanh regularization of sign(phidot)
  double torsion_stiffness = 0.0;   ///< k_CR (N m/rad), cable / flex
  double torsion_zero = 0.0;        ///< phi_0 (rad), where the cable torque vanishes
  double cogging_torque = 0.0;      ///< T_cog (N m): motor cogging -T_cog sin(N phi + psi_cog)
  int cogging_order = 0;            ///< N, cycles per turn (0 = none)
  double cogging_phase = 0.0;       ///< psi_cog (rad)
  /// A cogging map: more orders, each -T_k sin(N_k phi + psi_k), added to the one above.
  struct CoggingHarmonic {
    int order = 0;        ///< N_k, cycles per turn (>= 1)
    double torque = 0.0;  ///< T_k (N m)
    double phase = 0.0;   ///< psi_k (rad)
  };
  std::vector<CoggingHarmonic> cogging_map;
};

/// The cogging torque on phi: -T_cog sin(N phi + psi_cog) - sum_k T_k sin(N_k phi + psi_k) (N m).
double cogging_torque_at(const DiskRotorParams& p, double phi);

/// The highest cogging order of the rotor (0 without cogging).
int highest_cogging_order(const DiskRotorParams& p);

/// Components of gravity perpendicular to the gimbal axis, in the gimbal frame (m/s^2).
struct GimbalGravity {
  double gy = 0.0;
  double gz = 0.0;
};

/// Gravity in the gimbal frame for turntable angle theta, with the gimbal axis tilted by
/// `tilt` (rad) from the turntable axis towards azimuth `tilt_azimuth` (rad, in the
/// turntable's y-z plane, turning with it).
GimbalGravity gravity_in_gimbal(double g, double theta, double tilt = 0.0, double tilt_azimuth = 0.0);

/// State (phi, phidot, y, ydot, z, zdot).
using DiskState = std::array<double, 6>;

/// Accelerations (phi'', y'', z'') for motor torque M.
std::array<double, 3> disk_accelerations(const DiskRotorParams& p, const GimbalGravity& g, const DiskState& s,
                                         double motor_torque);

/// phi'' of the rigid rotor on quasi-static supports: Q_phi / (J + m e^2) (see above).
double rigid_axis_acceleration(const DiskRotorParams& p, const GimbalGravity& g, double phi, double phidot,
                               double motor_torque);

/// Mechanical energy T + V (J), conserved with motor, friction and damping off.
double disk_energy(const DiskRotorParams& p, const GimbalGravity& g, const DiskState& s);

/// Motor torque that holds the disk at rest at angle phi (support deflected statically):
/// m e (g_y sin p - g_z cos p) + k_CR (phi - phi_0) = m g e sin(theta + p) + cable.
double holding_torque(const DiskRotorParams& p, const GimbalGravity& g, double phi);

/// Static support deflection (y, z) at rest at angle phi.
std::array<double, 2> static_deflection(const DiskRotorParams& p, const GimbalGravity& g);

}  // namespace poise::models
