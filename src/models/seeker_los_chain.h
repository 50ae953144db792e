#pragma once
/// Two-axis (yaw over pitch) seeker: exact line-of-sight kinematics with shafting errors.
///
/// Source: Wang, Zhu, Yan, Jia, Sun 2011, "Analysis of LOS pointing error derived from
/// precision of shafting in stabilization mechanism", Infrared and Laser Engineering
/// 40(11):2265-2269 (docs/papers.md). The paper propagates its error terms with
/// first-order formulas (Sec. 3); here the chain is composed exactly and the paper's
/// formulas serve as the first-order check (tests/models/seeker_los_chain_test.cc).
///
/// Frames (right-handed): base B with x along the LOS at zero, z along the nominal yaw
/// axis. Yaw frame Y = O1(alpha) in B, pitch frame P = O2(beta) in Y, optical axis l in P:
///
///   d(alpha, beta) = O1(alpha) O2(beta) l,          |d| = 1
///   O_k(phi)       = T(a_k -> u_k(phi)) R(a_k, phi)  (rotation about the nominal axis a_k,
///                                                    then the axis tilt T carries the frame)
///   u_k(phi)       = normalize(a_k + t1(phi) e1 + t2(phi) e2)
///   t(phi)         = s + sum_h A_h (cos(n_h phi + psi_h), sin(n_h phi + psi_h))
///   T(a -> u)      = I + [v]x + [v]x^2 / (1 + c),   v = a x u, c = a . u  (minimal rotation)
///   l              = normalize(1, c3, 0)             (optical axis in P)
///
/// yaw:   a1 = z, (e1, e2) = (x, y); static tilt s from the yaw axis' perpendicularity to
///        the base (magnitude and direction).
/// pitch: a2 = -y (so +beta raises the LOS), (e1, e2) = (x, z); s = (0, c2), c2 the pitch
///        axis' departure from perpendicularity to the yaw axis.
/// c3:    the optical axis' departure from perpendicularity to the pitch axis.
/// Bearing terms: a shaft centre displaced by dA(phi) at bearing A and dB(phi) at bearing B,
/// a span L apart, points along L a + dB - dA, so each displacement harmonic of amplitude
/// e at one bearing adds a tilt harmonic of amplitude e / L (sign by bearing). Errors that
/// turn with the shaft (run-out) are functions of the shaft angle, never constants.
///
/// Nominal LOS n(alpha, beta) = (cos b cos a, cos b sin a, sin b). Pointing error:
///   total = angle(d, n) = 2 asin(|d - n| / 2)
///   yaw   = atan2(d.y, d.x) - alpha     (yaw-angle error, the paper's Delta alpha)
///   pitch = asin(d.z) - beta            (the paper's Delta beta)
/// First-order limits (checked in tests, they are the theodolite axis-error formulas the
/// paper uses): a yaw-axis tilt i towards azimuth psi gives yaw = -i tan(b) sin(a - psi),
/// pitch = -i cos(a - psi); c2 gives yaw = +c2 tan(b); c3 gives yaw = c3 / cos(b).
#include <Eigen/Dense>
#include <array>
#include <span>
#include <vector>

namespace poise::models {

/// One harmonic of an axis' tilt: amplitude (rad) t, order n (cycles per shaft turn,
/// 0 = static offset in direction psi), phase psi (rad).
struct TiltHarmonic {
  double amplitude = 0.0;
  double order = 0.0;
  double phase = 0.0;
};

/// The tilt of one axis as a function of its shaft angle.
struct AxisErrorState {
  static constexpr int kMaxHarmonics = 24;
  std::array<double, 2> static_tilt{0.0, 0.0};  ///< (t1, t2) in rad
  int n_harmonics = 0;
  std::array<TiltHarmonic, kMaxHarmonics> harmonics{};

  /// Appends a harmonic; throws poise::Error past kMaxHarmonics.
  void add(const TiltHarmonic& h);
  /// t(phi) = s + sum_h A_h (cos(n_h phi + psi_h), sin(n_h phi + psi_h)).
  Eigen::Vector2d tilt(double phi) const;
};

/// One realization of every geometric error of the seeker (one Monte Carlo sample).
struct SeekerErrorState {
  AxisErrorState yaw;
  AxisErrorState pitch;
  double collimation = 0.0;  ///< c3 (rad)
};

/// Pointing error at one gimbal angle (rad).
struct PointingError {
  double total = 0.0;
  double yaw = 0.0;
  double pitch = 0.0;
};

/// The smallest rotation taking one unit vector onto another. Undefined for opposite
/// vectors (1 + cos = 0); callers pass small tilts only.
Eigen::Matrix3d minimal_rotation(const Eigen::Vector3d& from_unit, const Eigen::Vector3d& to_unit);
Eigen::Matrix3d yaw_orientation(const AxisErrorState& yaw, double alpha);
Eigen::Matrix3d pitch_orientation(const AxisErrorState& pitch, double beta);
Eigen::Vector3d optical_axis(double collimation);
Eigen::Vector3d nominal_los(double alpha, double beta);
/// Exact LOS direction in the base frame.
Eigen::Vector3d los_direction(const SeekerErrorState& s, double alpha, double beta);
/// Error of the unit LOS d against the nominal LOS at (alpha, beta).
PointingError pointing_error(const Eigen::Vector3d& d, double alpha, double beta);

/// A yaw x pitch grid of gimbal angles and the per-thread buffers to evaluate a sample
/// on it. The chain factorizes: O1 depends on alpha only, O2 l on beta only, so a grid
/// costs n_alpha + n_beta frame builds and one 3x3 product per point.
///
/// Harmonic sums on the grid (the hot path): by angle addition,
///   sum_h A_h e^{i (n_h phi_k + psi_h)} = sum_n C_n w_n(phi_k),
///   C_n = sum_{h: n_h = n} A_h e^{i psi_h},   w_n(phi_k) = e^{i n phi_k},
/// so a sample costs one sincos per harmonic (its phase) and one complex multiply-add per
/// distinct order and grid point. The tables w_n are the same for every sample (the
/// orders come from the model): each thread's Workspace computes a table the first time
/// it meets an order, directly (sincos of n phi_k), so nothing accumulates along the grid
/// (no recurrence drift, any spacing, any real order). Checked against the direct form
/// AxisErrorState::tilt to 1e-12 relative in tests/kinds/seeker_los_harmonics_test.cc. The row of
/// errors over beta is branch-free and vectorized (SSE2, AVX2 where the CPU has it).
class LosGrid {
 public:
  LosGrid(std::vector<double> alpha, std::vector<double> beta);
  std::size_t size() const { return alpha_.size() * beta_.size(); }
  const std::vector<double>& alpha() const { return alpha_; }
  const std::vector<double>& beta() const { return beta_; }
  /// Row-major index: point (ia, ib) -> ia * n_beta + ib.
  std::size_t index(std::size_t ia, std::size_t ib) const { return ia * beta_.size() + ib; }

  /// e^{i n phi_k} over one axis' angles for one order n (cos in c, sin in s).
  struct PhaseTable {
    double order = 0.0;
    std::vector<double> c, s;
  };
  struct Workspace {
    std::vector<Eigen::Matrix3d> yaw_frames;
    std::vector<Eigen::Vector3d> pitch_los;
    std::vector<PhaseTable> yaw_phases, pitch_phases;  ///< filled on first use of an order
    std::vector<Eigen::Vector2d> tilts;                ///< one axis' tilt at each of its angles
    std::vector<double> pitch_xyz;                     ///< pitch LOS as x[], y[], z[] (the vectorized row loop)
    std::vector<double> row;                           ///< one yaw angle's errors over beta and their series' arguments
  };
  Workspace make_workspace() const;
  /// Fills out (size()) with the pointing error at every grid point.
  void evaluate(const SeekerErrorState& s, Workspace& ws, std::span<PointingError> out) const;
  /// t(phi) at every angle of `phi` (the grid's alpha or beta) by the grouped sum above;
  /// `tables` caches the phase tables of that angle list. out.size() == phi.size().
  static void tilts_on_grid(const AxisErrorState& axis, std::span<const double> phi, std::vector<PhaseTable>& tables,
                            std::span<Eigen::Vector2d> out);

 private:
  std::vector<double> alpha_, beta_;
  std::vector<double> ca_, sa_, cb_, sb_;
};

/// Evenly spaced angles from lo to hi inclusive (n >= 2), or {lo} when n == 1.
std::vector<double> linspace(double lo, double hi, std::size_t n);

}  // namespace poise::models
