#pragma once
/// Vertical hard-bearing balancing machine on spring plates (Wang & Wang 2014, Secs. 2-4,
/// Eqs. 1-2, 8-17; docs/papers.md), derived anew; the printed equations have slips.
///
/// Mechanism (paper Figs. 6-7): a support board hangs on two horizontal spring plates
/// (stiffness k5 each) and translates by x; a torsion shaft fixed to the board carries the
/// spindle system (spindle, support, test rotor), which swings about the shaft by theta and is
/// restrained by a torsional spring plate k6 acting at lever l (sensor 2 sits there).
/// Sensor 1 measures x at the height of the shaft. M: all mass that translates (board,
/// shaft, spindle system); m: the swinging spindle system; H: height of its mass centre O4
/// above the shaft axis; J: its moment of inertia about the axis through O4 parallel to the
/// shaft; h: height of the static unbalance above the shaft.
///
/// Spring plates (beam theory, small deflection, plate = beam of width w):
///   * Horizontal plate: a fixed-guided beam bending about its thin axis. One end is clamped
///     to the base, the other to the board, which two parallel plates keep from turning
///     (a parallelogram), so the end translates without rotation:
///       k = 12 E I / L^3,  I = w t^3 / 12  =>  k = E w t^3 / L^3,
///       end moments F L / 2  =>  sigma_max = 6 (F L / 2) / (w t^2) = 3 F L / (w t^2).
///   * Torsional plate: the plate of stiffness k6 = 12 E I / L^3, clamped to the base at one end,
///     its other end attached at lever l from the torsion axis; it lies along the lever, so a
///     swing theta moves that end by v = l theta. What the end's rotation phi is, is the end
///     condition (model key torsional_plate.end_condition, TorsionPlateEnd):
///       guided                 phi = 0 (a linkage keeps the end parallel; the paper's reading)
///       clamped_base_inboard   phi = +theta: clamped to the swinging support, the base clamp
///                              between the axis and the attachment
///       clamped_base_outboard  phi = -theta: clamped, the base clamp beyond the attachment
///       pinned                 moment-free end (phi free)
///     Beam stiffness matrix of the plate (base fixed), end force F and end moment M:
///       F = E I / L^3 (12 v - 6 L phi),  M = E I / L^3 (-6 L v + 4 L^2 phi),
///     virtual work of (F, M) through (v, phi) = (l, +-1) dtheta gives the restoring moment
///     about the axis K_rot theta = F l +- M, and sensor 2 (a force sensor in the plate, at l)
///     reads F. With rho = L / l:
///       end condition      K_rot / (k6 l^2)          F / (k6 l theta)   M / (F l) (clamp share)
///       guided             1                         1                  0 (taken by the guide)
///       clamped inboard    1 - rho + rho^2 / 3       1 - rho / 2        (4 rho^2 - 6 rho) / (12 - 6 rho)
///       clamped outboard   1 + rho + rho^2 / 3       1 + rho / 2        (4 rho^2 + 6 rho) / (12 + 6 rho)
///       pinned             1 / 4                     1 / 4              0
///     At the Wang 2014 model's rho = 0.32 the clamped ends give 0.714 and 1.354 times k6 l^2,
///     and the clamp moment carries -15% and +17% of sensor 2's load F l: F l is then not the
///     moment the closed form assumes (torsion_plate_split; tested against an independent
///     solution of E I w^(4) = 0 with these end conditions, tests/models/torsion_plate_test.cc).
///     The guided end is exact only for L << l.
///   * Sensor 1 is a force sensor in ONE horizontal plate: the pair carries F = (k5,1 + k5,2) x,
///     sensor 1 reads k5,1 x = k5,1 / (k5,1 + k5,2) F. With as-built plates of unequal
///     stiffness the closed form's U = 2 F_n1 / w^2 is off by 2 k5,1 / (k5,1 + k5,2) - 1
///     (about half the plates' relative stiffness difference).
///
/// Equations of motion (Lagrange, small angles, linear as Eq. 8). Mass centre of the swinging
/// part at (x + H sin theta, H cos theta), hence
///   T = 1/2 (M - m) x'^2 + 1/2 m ((x' + H cos theta theta')^2 + (H sin theta theta')^2)
///       + 1/2 J theta'^2  =  1/2 M x'^2 + m H cos theta x' theta' + 1/2 (J + m H^2) theta'^2
///   V = 1/2 (2 k5) x^2 + 1/2 k6 l^2 theta^2 + m g H cos theta
/// Unbalance forcing: the horizontal (in-plane) component of the rotating centrifugal force,
/// F = U w^2 cos(w t + a3), acts at height h: virtual work F d(x + h sin theta); the couple
/// T = V w^2 cos(w t + a4) acts on theta. Viscous damping c_x on x, c_theta on theta.
/// Linearized (theta ~ 1e-5 rad in service, cos theta - 1 ~ 1e-10):
///   M x'' + m H theta'' + c_x x' + 2 k5 x = F
///   m H x'' + (J + m H^2) theta'' + c_theta theta' + (k6 l^2 - m g H) theta = F h + T
/// i.e. M_q q'' + C q' + K q = f with the symmetric mass matrix
///   M_q = [[M, m H], [m H, J + m H^2]],  K = diag(2 k5, k6 l^2 - m g H).
/// Steady state at speed w: q = Re(X e^{i w t}), (K - w^2 M_q + i w C) X = f^,
///   f^ = w^2 (U e^{i a3}, U h e^{i a3} + V e^{i a4}).
///
/// Eq. 8 as printed:  M x'' + m H theta'' + 2 k5 x = F,
///                    J theta'' + m (x'' + H theta'') H + k6 l^2 theta = F h + T.
/// This agrees with the derivation above (gravity and damping off) provided J is about the
/// mass centre O4: m H x'' belongs in both rows (the mass matrix is symmetric), and m H^2 is
/// the parallel-axis term. Corrections and readings (checked in
/// tests/models/spring_plate_machine_test.cc):
///   * Eq. 8's text calls J the inertia "about the rotation center"; read as the torsion axis,
///     m H^2 would be counted twice. J here is about O4; J + m H^2 is about the shaft.
///   * Eq. 8 drops gravity: the swinging part is an inverted pendulum (mass centre above the
///     shaft), the torsional stiffness is k6 l^2 - m g H. Off by default (gravity = 0) to match
///     the paper; m g H = 0.05 % of k6 l^2 for the plausible Wang 2014 values of the test.
///   * Eq. 9's omega_n2 = sqrt(k6 l^2 / (J + m h^2)): h for H; Eq. 10 itself uses J + m H^2.
///     omega_n1, omega_n2 are the uncoupled frequencies; the coupled natural frequencies
///     (generalized eigenproblem) lie outside them, omega_1 < min and omega_2 > max.
///   * Eq. 11 (hard-bearing limit) drops the factor h: k6 l^2 theta = U h w^2 cos(w t + a3)
///     + V w^2 cos(w t + a4). Evidence: Eqs. 15-16 of the paper carry U h; the paper's own
///     Fig. 9 (sensor 2 proportional to the height of the test mass) contradicts the printed
///     form; and Eq. 8's right-hand side is F h + T.
///   * Eq. 13 inherits it and is dimensionally wrong as printed (N m minus N):
///     V e^{i a4} = (F_n2 l - 2 F_n1 h) / w^2.
///   * Eq. 14 mixes symbols (k1, k2, m1 for k5, k6, m), writes m w^2 for M w^2 in (2 k5 - M w^2)
///     and in theta's m h w^2 (-> M h w^2), and loses the parentheses of the denominator
///     D = (2 k5 - M w^2)(k6 l^2 - (J + m H^2) w^2) - m^2 H^2 w^4. Exact solution (c = 0):
///       x     = [F (k6 l^2 - (J + m H^2) w^2) + m H w^2 (F h + T)] / D
///       theta = [(2 k5 - M w^2)(F h + T) + m H w^2 F] / D
///   * Eq. 15 keeps m H V w^4 / (2 k5 k6 l^2) in x while dropping terms of the same order: it
///     is the leading cross-talk of the couple unbalance into sensor 1, relative size
///     (m H w^2 / k6 l^2) V / U, which matters because V >> U on satellite antennas.
///   * Eq. 17 drops h and the w^2 of the couple term: F_n2 l = U h w^2 cos(w t + a3)
///     + V w^2 cos(w t + a4) (the printed V cos(...) is kg m^2 beside N m).
///   * Eq. 2 takes the couple about the coordinate origin (V = sum U_i z_i), while Eq. 8
///     applies F at height h and adds T = V w^2: both together count U h twice unless V is
///     the couple about height h. Here V = sum U_i (z_i - h), so F h + T = w^2 sum U_i z_i
///     for any reference h. Eq. 2's k x only turns the vector to name the moment's axis; the
///     in-plane phase a4 is that of sum U_i (z_i - h).
#include <complex>
#include <span>
#include <string>

#include <Eigen/Core>

namespace poise::models {

// ---- spring plates ----------------------------------------------------------------------

/// A flat spring plate; bending is about its thin axis (deflection along the thickness).
struct SpringPlate {
  double length = 0.0;          ///< L (m), free length between the clamps
  double width = 0.0;           ///< w (m)
  double thickness = 0.0;       ///< t (m)
  double youngs_modulus = 0.0;  ///< E (Pa); spring steel about 206 GPa
};

/// I = w t^3 / 12 (m^4). Throws poise::Error naming the field if a dimension is not > 0.
double plate_second_moment(const SpringPlate& plate);
/// Fixed-guided beam stiffness k = 12 E I / L^3 = E w t^3 / L^3 (N/m).
double guided_plate_stiffness(const SpringPlate& plate);
/// Static end deflection F / k (m) of the fixed-guided plate under end force F (N).
double guided_plate_deflection(const SpringPlate& plate, double end_force);
/// Largest bending stress (Pa), at the clamps: 3 |F| L / (w t^2).
double guided_plate_max_stress(const SpringPlate& plate, double end_force);
/// Euler load (N) of the fixed-guided plate compressed along its length: both ends clamped
/// against rotation, one free to sway (effective length L): P_cr = pi^2 E I / L^2.
double guided_column_buckling_load(const SpringPlate& plate);
/// Lateral stiffness (N/m) of the fixed-guided plate carrying an axial compression P (N), from
/// the beam-column equation E I w^(4) + P w^(2) = 0 with w(0) = w'(0) = w'(L) = 0, w(L) = d:
///   k = E I q^3 sin(qL) / (2 - 2 cos(qL) - qL sin(qL)),  q = sqrt(P / (E I)).
/// k = 12 E I / L^3 at P = 0, ~ 12 E I / L^3 - 6 P / (5 L) for small P (the weight softens
/// the plates), 0 at the Euler load (negative beyond: the plate has buckled).
double guided_column_lateral_stiffness(const SpringPlate& plate, double axial_load);
/// Rotational stiffness k6 l^2 (N m/rad) of a plate of stiffness k6 acting at lever l
/// (guided end; see TorsionPlateSplit for the others).
double rotational_stiffness(double plate_stiffness, double lever);

/// End condition of the torsional plate's attachment to the swinging support (header above).
enum class TorsionPlateEnd { kGuided, kClampedBaseInboard, kClampedBaseOutboard, kPinned };

/// "guided", "clamped_base_inboard", "clamped_base_outboard", "pinned".
const char* torsion_plate_end_name(TorsionPlateEnd e);

/// How the torsional plate's load splits, for plate length L and lever l (table above).
struct TorsionPlateSplit {
  double rotation_factor = 1.0;  ///< K_rot / (k6 l^2)
  double force_factor = 1.0;     ///< sensor 2's F / (k6 l theta)
  double moment_share = 0.0;     ///< end moment / (F l), signed as it adds to F l about the axis
};
TorsionPlateSplit torsion_plate_split(TorsionPlateEnd end, double plate_length, double lever);

/// Largest bending moment in the torsional plate (N m) at swing theta (both clamps and the end).
double torsion_plate_max_moment(const SpringPlate& plate, TorsionPlateEnd end, double lever, double theta);

// ---- machine -----------------------------------------------------------------------------

struct SpringPlateMachineParams {
  double total_mass = 0.0;                  ///< M (kg), everything that translates by x
  double rotating_mass = 0.0;               ///< m (kg), the swinging spindle system, m <= M
  double mass_centre_height = 0.0;          ///< H (m), O4 above the torsion shaft axis
  double inertia = 0.0;                     ///< J (kg m^2), swinging part about O4
  double lever = 0.0;                       ///< l (m), torsional plate / sensor 2 from the axis
  double horizontal_plate_stiffness = 0.0;  ///< k5 (N/m), the mean of the two plates: 2 k5 = k5,1 + k5,2
  /// k5,1 (N/m): the plate that carries sensor 1; 0 = horizontal_plate_stiffness (equal plates).
  double sensor_1_plate_stiffness = 0.0;
  double torsional_plate_stiffness = 0.0;  ///< k6 (N/m)
  /// Torsional plate's end condition: K_rot = rotation_factor k6 l^2, sensor 2 reads
  /// force_factor k6 l theta (TorsionPlateSplit; guided = 1, 1, 0).
  TorsionPlateSplit torsion_split;
  double damping_x = 0.0;      ///< c_x (N s/m)
  double damping_theta = 0.0;  ///< c_theta (N m s/rad)
  double gravity = 0.0;        ///< g (m/s^2); 0 = Eq. 8 (pendulum term off)
};

/// Throws poise::Error naming the field, its value and the constraint violated.
void validate(const SpringPlateMachineParams& p);

/// Unbalance as Eq. 8 takes it: U at height h plus the couple V about that height.
struct SpringPlateUnbalance {
  double static_unbalance = 0.0;  ///< U (kg m)
  double static_phase = 0.0;      ///< a3 (rad)
  double height = 0.0;            ///< h (m) above the torsion shaft axis
  double couple_unbalance = 0.0;  ///< V (kg m^2), couple about height h
  double couple_phase = 0.0;      ///< a4 (rad)
};

Eigen::Matrix2d mass_matrix(const SpringPlateMachineParams& p);       ///< [[M, mH], [mH, J+mH^2]]
Eigen::Matrix2d stiffness_matrix(const SpringPlateMachineParams& p);  ///< diag(2k5, K_rot - m g H)
Eigen::Matrix2d damping_matrix(const SpringPlateMachineParams& p);    ///< diag(c_x, c_theta)

struct NaturalFrequencies {
  double omega_1 = 0.0;      ///< lower coupled natural frequency (rad/s)
  double omega_2 = 0.0;      ///< upper (rad/s)
  double omega_x = 0.0;      ///< uncoupled sqrt(2 k5 / M) (Eq. 9's omega_n1)
  double omega_theta = 0.0;  ///< uncoupled sqrt(K_tt / (J + m H^2)) (Eq. 9's omega_n2, corrected)
  Eigen::Matrix2d modes;     ///< columns: mode shapes (x, theta), mass-normalized
};

/// Undamped natural frequencies: K phi = w^2 M_q phi (generalized symmetric eigenproblem).
NaturalFrequencies natural_frequencies(const SpringPlateMachineParams& p);

/// Complex amplitudes of the generalized forces (F, F h + T) at speed omega (rad/s).
Eigen::Vector2cd unbalance_forcing(const SpringPlateUnbalance& u, double omega);

/// Steady-state complex amplitudes X = (x^, theta^), q(t) = Re(X e^{i omega t}): exact
/// solution of (K - omega^2 M_q + i omega C) X = f^.
Eigen::Vector2cd steady_state_response(const SpringPlateMachineParams& p, const SpringPlateUnbalance& u, double omega);

/// Hard-bearing limit (omega << omega_1), Eq. 11 corrected: X = K^{-1} f^, i.e.
/// x^ = U w^2 e^{i a3} / (2 k5), theta^ = (U h e^{i a3} + V e^{i a4}) w^2 / (k6 l^2 - m g H).
Eigen::Vector2cd hard_bearing_response(const SpringPlateMachineParams& p, const SpringPlateUnbalance& u, double omega);

/// Sensor forces, Eq. 12 as built: (F_n1, F_n2) = (k5,1 x, force_factor k6 l theta), complex
/// amplitudes (N); Eq. 12 as printed for equal plates and a guided torsional plate.
Eigen::Vector2cd sensor_forces(const SpringPlateMachineParams& p, const Eigen::Vector2cd& response);

/// Eq. 13 corrected (hard-bearing limit, gravity off): U e^{i a3} = 2 F_n1 / w^2 and
/// V e^{i a4} = (F_n2 l (1 + s) - 2 F_n1 h) / w^2, s the clamp-moment share of `p`'s
/// torsion_split (0 for the guided plate: Eq. 13 itself). Uses of `p` only l and the split,
/// nothing of k5 or k6: in the hard-bearing limit F_n1 = F / 2 and F_n2 l (1 + s) = F h + T
/// whatever the plate stiffnesses, provided the two horizontal plates are equal. Returns the
/// unbalance with static_phase and couple_phase from the complex values.
SpringPlateUnbalance unbalance_from_sensor_forces(const SpringPlateMachineParams& p, const Eigen::Vector2cd& sensor,
                                                  double omega, double height);

struct HardBearingCheck {
  bool ok = false;
  double ratio = 0.0;  ///< omega_1 / omega (lowest coupled natural frequency over speed)
  /// Largest relative deviation of the exact response from the hard-bearing limit: x for a
  /// pure static unbalance at the shaft height, theta for a pure couple (given damping).
  double deviation = 0.0;
  std::string message;
};

/// Hard-bearing condition: omega_1 >= factor * omega. Default factor 3 is a common design
/// rule for hard-bearing machines (not from the paper): the single-DOF magnification
/// 1 / (1 - r^2) then exceeds 1 by at most 12.5 %; a factor of 10 gives about 1 %.
HardBearingCheck check_hard_bearing(const SpringPlateMachineParams& p, double omega, double factor = 3.0);

/// Speed in r/min to rad/s.
inline double rpm_to_rad_per_s(double rpm) { return rpm * 2.0 * 3.14159265358979323846 / 60.0; }

// ---- Eqs. 1-2: correction-plane masses to U and V ----------------------------------------

struct PlaneMass {
  double mass = 0.0;    ///< kg
  double radius = 0.0;  ///< m
  double angle = 0.0;   ///< rad, in the rotor frame
  double height = 0.0;  ///< z (m) above the torsion shaft axis
};

struct ResultantUnbalance {
  std::complex<double> static_unbalance;  ///< U = sum m r e^{i a} (kg m), Eq. 1
  std::complex<double> couple_unbalance;  ///< V = sum m r (z - h) e^{i a} (kg m^2), Eq. 2 about h
  double height = 0.0;                    ///< reference height h (Eq. 2 as printed: 0)
};

/// Eqs. 1-2 for masses on any number of planes, the couple taken about height h.
ResultantUnbalance resultant_unbalance(std::span<const PlaneMass> masses, double height);

/// The same as Eq. 8's forcing input (magnitudes and phases).
SpringPlateUnbalance to_machine_unbalance(const ResultantUnbalance& r);

// ---- time domain -------------------------------------------------------------------------

/// State y = (x, x', theta, theta').
/// Mechanical energy 1/2 q'^T M_q q' + 1/2 q^T K q (J), conserved unforced and undamped.
double mechanical_energy(const SpringPlateMachineParams& p, const double* y);

/// User data of spring_plate_rhs: the machine, the unbalance and the speed (rad/s). The
/// rotor spins at constant speed from t = 0, angle omega t.
struct SpringPlateRhsData {
  SpringPlateMachineParams params;
  SpringPlateUnbalance unbalance;
  double omega = 0.0;
};

/// Right-hand side dy/dt for SUNDIALS (solvers::RhsFunction): user_data points to a
/// SpringPlateRhsData. Never throws; returns 0, or -1 (fatal) if user_data is null.
/// The 2x2 mass matrix is inverted in closed form (det M_q = M (J + m H^2) - m^2 H^2 > 0).
int spring_plate_rhs(double t, const double* y, double* ydot, void* user_data);

}  // namespace poise::models
