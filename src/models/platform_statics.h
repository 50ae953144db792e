#pragma once
/// Statics of a three-gimbal inertial stabilization platform: the coupled unbalance torques
/// of the inner, middle and outer gimbal axes under gravity and carrier acceleration
/// (Yang, Zhao, Li, Wu 2015, Sec. 2, Eqs. 1-12; docs/papers.md),
/// derived anew with rotation matrices.
///
/// Frames (the paper's Fig. 2): base b; outer o turned by alpha about x_b; middle m turned by
/// beta about z_o; inner p turned by gamma about y_m. The three axes meet at one point, the
/// origin of every frame. Active rotations (body -> parent components):
///   base_from_outer  = Rx(alpha),  outer_from_middle = Rz(beta),  middle_from_inner = Ry(gamma)
/// and the paper's transforms are their transposes: C_b^o = Rx(alpha)^T, C_o^m = Rz(beta)^T,
/// C_m^p = Ry(gamma)^T.
///
/// Eqs. 1-3: the specific force f in each frame, f_o = C_b^o f_b, f_m = C_o^m f_o,
/// f_p = C_m^p f_m, with f_b = (0, 0, -g) for gravity alone and f_b = g_b - a_b when the
/// carrier accelerates by a_b (d'Alembert: the inertial force -m a joins the weight m g).
///
/// A gimbal k is described by its mass m_k and first moment S_k = m_k r_k (kg m) in its own
/// frame (counterweights add to both). The assembly outboard of an axis and its first moment
/// in that gimbal's frame:
///   inner : S^p = S_p
///   middle: S^m = S_m + Ry(gamma) S_p
///   outer : S^o = S_o + Rz(beta) (S_m + Ry(gamma) S_p)
/// The gravity (and inertial) torque on the assembly about the common centre, in that
/// gimbal's frame, is tau = S^k x f_k, and the torque on the axis is its component along the
/// axis: inner y, middle z, outer x. The paper writes M = m [g~] r = f x S = -tau (Eqs. 4, 7,
/// 10): the torque the motor must apply to hold the gimbal. Both are returned.
///
/// Checks against the printed expansions (tests/models/platform_statics_test.cc, random angles and
/// centroids, to 1e-12): Eqs. 1-3 agree with the rotation matrices. Eqs. 4, 7, 10, 11 agree
/// term by term with f x S except where the two OCR transcriptions of the paper differ:
///   * Eq. 7, M_my: OCR 001 prints "-m_p g y_p sin a sin b sin c"; the derivation (and OCR
///     000) give -m_p g x_p sin a sin b sin c. With y_p the printed M_my is wrong by
///     m_p g (x_p - y_p) sin a sin b sin c.
///   * Eq. 7, M_mx: OCR 000 prints "-m_m g x_m sin a cos b"; the derivation (and OCR 001)
///     give -m_m g z_m sin a cos b.
///   * Eq. 4, M_px: OCR 000 prints "m_p g x_p sin a sin b sin c"; the derivation (and OCR
///     001) give m_p g y_p sin a sin b sin c.
///   * Eq. 10, M_oy: both OCRs lose the sign between "... cos b cos c" and
///     "m_p g y_p cos a sin b"; the derivation gives "+".
///   * Sign: "unbalance torque" M = m [g~] r is minus the gravity torque r x m g; it is
///     the holding torque. Harmless for the balance conditions (M = 0), it matters when the
///     torque is fed to a servo as a disturbance.
/// The balance conditions Eqs. 6, 9, 12 follow exactly from the axis components (they hold
/// for every alpha, beta, gamma only if the listed coefficients vanish).
/// Carrier acceleration (end of Sec. 2): replace g_b by the specific force g_b - a_b; the
/// torques are linear in it, so tau_axis = c_k . f_b with c_k = axis_k x S^k (base frame).
#include <Eigen/Dense>
#include <array>

namespace poise::models {

/// Gimbal angles (rad): outer alpha about x_b, middle beta about z_o, inner gamma about y_m.
struct GimbalAngles {
  double alpha = 0.0;
  double beta = 0.0;
  double gamma = 0.0;
};

/// Mass properties of one gimbal (with what it carries) in its own frame, about the
/// common centre of the axes.
struct GimbalBody {
  double mass = 0.0;                                       ///< kg
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();  ///< m r (kg m)
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();       ///< about the centre (kg m^2)

  Eigen::Vector3d centroid() const { return mass > 0 ? Eigen::Vector3d(first_moment / mass) : Eigen::Vector3d::Zero(); }
  /// Adds a point mass (a counterweight) at position p (m) of this gimbal's frame.
  void add_point_mass(double m, const Eigen::Vector3d& p);
};

enum class Axis { kInner = 0, kMiddle = 1, kOuter = 2 };
inline constexpr std::array<Axis, 3> kAllAxes{Axis::kInner, Axis::kMiddle, Axis::kOuter};
const char* axis_name(Axis a);  ///< "inner", "middle", "outer"
/// Index (0, 1, 2) of the gimbal's rotation axis in its own frame: inner y, middle z, outer x.
int axis_component(Axis a);

struct Platform {
  GimbalBody inner, middle, outer;
  GimbalBody& body(Axis a) { return a == Axis::kInner ? inner : (a == Axis::kMiddle ? middle : outer); }
  const GimbalBody& body(Axis a) const { return a == Axis::kInner ? inner : (a == Axis::kMiddle ? middle : outer); }
};

Eigen::Matrix3d rot_x(double a);
Eigen::Matrix3d rot_y(double a);
Eigen::Matrix3d rot_z(double a);

/// Orientation of gimbal `a`'s frame in the base frame (body -> base components).
Eigen::Matrix3d base_from_gimbal(Axis a, const GimbalAngles& q);

/// Eqs. 1-3: specific force in the outer, middle and inner frames for f_b in the base frame.
struct FrameForces {
  Eigen::Vector3d outer, middle, inner;
};
FrameForces specific_force_in_frames(const GimbalAngles& q, const Eigen::Vector3d& f_base);

/// The assembly outboard of axis `a` (the gimbal and every gimbal it carries), in gimbal
/// `a`'s frame: total mass, first moment, inertia tensor about the centre.
GimbalBody outboard_assembly(const Platform& p, Axis a, const GimbalAngles& q);

/// Torques on each gimbal's assembly, each in its own frame (N m).
struct PlatformTorques {
  Eigen::Vector3d inner, middle, outer;  ///< tau = S x f: gravity / inertial torque
  /// Axis components: inner y, middle z, outer x (the disturbance the axis servo sees).
  std::array<double, 3> axis{};  ///< indexed by Axis
  /// The paper's M = f x S = -tau (Eqs. 4, 7, 10), the holding torque.
  Eigen::Vector3d paper(Axis a) const { return -(a == Axis::kInner ? inner : (a == Axis::kMiddle ? middle : outer)); }
};
PlatformTorques unbalance_torques(const Platform& p, const GimbalAngles& q, const Eigen::Vector3d& f_base);

/// c_k = axis_k x S^k in the base frame (N m per m/s^2): the axis torque is c_k . f_base.
std::array<Eigen::Vector3d, 3> torque_sensitivities(const Platform& p, const GimbalAngles& q);

/// The printed expansions (OCR 001 transcription), gravity only, for the comparison in the
/// tests. Centroids r_k and masses m_k as in the paper.
struct PrintedInputs {
  double g = 9.80665;
  double m_p = 0, m_m = 0, m_o = 0;
  Eigen::Vector3d r_p = Eigen::Vector3d::Zero(), r_m = Eigen::Vector3d::Zero(), r_o = Eigen::Vector3d::Zero();
};
Eigen::Vector3d printed_eq1(const GimbalAngles& q, double g);
Eigen::Vector3d printed_eq2(const GimbalAngles& q, double g);
Eigen::Vector3d printed_eq3(const GimbalAngles& q, double g);
Eigen::Vector3d printed_eq4(const GimbalAngles& q, const PrintedInputs& in);
Eigen::Vector3d printed_eq7(const GimbalAngles& q, const PrintedInputs& in);
Eigen::Vector3d printed_eq10(const GimbalAngles& q, const PrintedInputs& in);

/// Line of sight (the inner x axis, Sec. 2) in the base frame.
Eigen::Vector3d line_of_sight(const GimbalAngles& q);
/// LOS angular error (rad) from small angle errors (rad) of the three axes, to first order:
/// |dw x d| with dw = d_alpha x_b + d_beta z_o + d_gamma y_m (a rotation about the LOS
/// itself does not move it).
double los_error_from_axis_errors(const GimbalAngles& q, double d_alpha, double d_beta, double d_gamma);

}  // namespace poise::models
