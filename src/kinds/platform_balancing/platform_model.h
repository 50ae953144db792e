#pragma once
/// A three-gimbal stabilization platform and its static-unbalance test rig
/// (models/platform_three_gimbal.toml): each gimbal's mass properties, motor, bearings and
/// correction plane, the test system of Yang 2015 Sec. 5 (servo, oscillation, acquisition,
/// turntable, solver), the platform's own stabilization loop, and every tolerance with its
/// scope ("unit": drawn once per platform as built; "test": drawn for each axis test).
///
/// Statics: models/platform_statics.h (Eqs. 1-12, derived and checked). The single-axis
/// test: procedures/static_unbalance_procedure.h.
///
/// Mapping of one axis test onto the disk rotor (models/disk_rotor.h). The gimbal under
/// test and every gimbal it carries (locked at their lock angles plus their locking errors)
/// turn about the tested axis k; the gimbals that carry it are locked and clamped with the
/// base in the fixture. For axis k (inner y_p, middle z_m, outer x_o) the disk's
/// (x, y, z) are the gimbal's axes (k, k+1, k+2) cyclically (inner: y, z, x; middle: z, x,
/// y; outer: x, y, z), right-handed, so the disk angle phi is the gimbal angle and at
/// turntable zero gravity lies along the disk's +y. With S = the outboard first moment
/// (kg m) and I the outboard inertia tensor about the centre, both in the tested gimbal's
/// frame, and M the outboard mass:
///   mass            = M
///   eccentricity    e = |(S_{k+1}, S_{k+2})| / M      (the part of S perpendicular to the axis)
///   its direction   eps = atan2(S_{k+2}, S_{k+1})    (in the disk's y-z plane, at phi = 0)
///   inertia about C J = I_kk - M e^2               (the disk model's J is about the mass centre)
/// The part of S along the axis (S_k) exerts no torque about it: the test cannot see it
/// (Eqs. 6, 9). The locking errors of the gimbals that carry the tested one tilt the axis
/// against the turntable axis (the disk's axis_tilt, with its azimuth in the disk's y-z
/// plane) and turn the fixture about it (added to the turntable zero); those of the gimbals
/// it carries move their mass (into S and I).
/// The counterweight (Eq. 23, m = MT_s / (R g)) goes at the fitted angle b + pi in the
/// disk's y-z plane, at radius R, in the gimbal's correction plane a distance h along the
/// axis: it adds m h to S_k, an unbalance of the next axes out, which the later tests see.
#include <array>
#include <map>
#include <string>

#include "engine/study_files/model_overrides.h"
#include "engine/study_files/tolerance_spec.h"
#include "models/platform_statics.h"
#include "models/stabilization_loop.h"
#include "procedures/static_unbalance_procedure.h"

namespace poise::kinds::platform_balancing {
using engine::ModelHeader;
using engine::ScopedTolerance;
using engine::ValidationError;

/// One gimbal: mass properties, its motor and bearings (the disk-rotor parameters of its
/// test), its correction plane and where it is locked while the others are tested.
struct PlatformGimbal {
  double mass = 0.0;                                   ///< kg, with what it carries alone
  Eigen::Vector3d inertia = Eigen::Vector3d::Zero();   ///< principal, about the centre (kg m^2)
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  ///< design centroid (m), own frame
  models::DiskRotorParams bearing;                     ///< friction, cable, support; mass / inertia / e set per test
  double kt_nominal = 0.0;                             ///< N m/A
  double current_limit = 0.0;                          ///< A
  double counterweight_radius = 0.0;                   ///< R of Eq. 23 (m)
  double counterweight_plane = 0.0;                    ///< h, axial position of the correction plane (m)
  double lock_angle = 0.0;                             ///< rad, while another axis is tested
};

struct PlatformModel : ModelHeader {        ///< file, name, title, source of the model file
  std::array<PlatformGimbal, 3> gimbals;    ///< indexed by models::Axis (inner, middle, outer)
  procedures::TestPlan plan;                ///< servo gains, oscillation, acquisition, turntable, solver
  models::StabilizationLoop stabilization;  ///< inertia set per axis
  // Tolerances (SI). Centroids: each component of each gimbal's centroid offset.
  std::array<ScopedTolerance, 3> centroid;  ///< indexed by Axis
  ScopedTolerance kt_calibration;           ///< K_T true / nominal - 1, each motor
  ScopedTolerance kt_drift;                 ///< further K_T change by the test
  ScopedTolerance lock_error;               ///< each locked gimbal in each test (rad)
  ScopedTolerance fixture_tilt;             ///< tested axis vs turntable axis (rad), random azimuth
  ScopedTolerance turntable_zero;           ///< rad
  ScopedTolerance gimbal_zero;              ///< registration of the tested gimbal's zero (rad)
  ScopedTolerance counterweight_mass;       ///< relative
  ScopedTolerance counterweight_radius;     ///< m
  ScopedTolerance counterweight_angle;      ///< rad
  ScopedTolerance counterweight_plane;      ///< axial placement (m)

  const PlatformGimbal& gimbal(models::Axis a) const { return gimbals[static_cast<std::size_t>(a)]; }
  /// The platform as designed (centroids at their design values, no counterweights).
  models::Platform nominal_platform() const;
  /// Lock angles of the three gimbals (outer alpha, middle beta, inner gamma).
  models::GimbalAngles lock_angles() const;
};

/// Loads and validates; `overrides` replace values by dotted key. Throws ValidationError.
PlatformModel load_platform_model(const std::string& path, const std::map<std::string, std::string>& overrides = {});

}  // namespace poise::kinds::platform_balancing
