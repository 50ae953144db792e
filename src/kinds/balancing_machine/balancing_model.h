#pragma once
/// The vertical hard-bearing balancing machine on spring plates (models/balancing_machine_*.toml,
/// Wang & Wang 2014): plates by geometry and material, the frame, the standard test rotor
/// with its testing surfaces, sensors, the measurement run, and every tolerance with its
/// distribution and scope (tolerance_spec.h: "unit" = as built, "test" = per run).
///
/// The swinging part is the spindle system plus the rotor on it; its mass m, mass-centre
/// height H and inertia J (about its mass centre) follow from the parts:
///   m = m_s + m_R,  H = (m_s z_s + m_R z_R) / m,
///   J = J_s + m_s (z_s - H)^2 + m_R (3 r^2 + h_R^2) / 12 + m_R (z_R - H)^2
/// (the rotor a solid cylinder of radius r = D/2 and height h_R whose centre is z_R above
/// the torsion shaft axis). M = m + board mass. Damping by uncoupled damping ratios:
///   c_x = 2 zeta_x sqrt(2 k5 M),  c_theta = 2 zeta_theta sqrt(k6 l^2 (J + m H^2)).
#include <map>
#include <string>
#include <vector>

#include "engine/study_files/model_overrides.h"
#include "engine/study_files/tolerance_spec.h"
#include "models/spring_plate_machine.h"
#include "procedures/balancing_measurement.h"

namespace poise::kinds::balancing_machine {
using engine::ModelHeader;
using engine::ScopedTolerance;
using engine::ValidationError;

/// A rotor on the spindle: a solid cylinder with numbered testing surfaces (planes).
struct BalancingRotor {
  double mass = 0.0;              ///< kg
  double diameter = 0.0;          ///< m
  double height = 0.0;            ///< m (length along the spin axis)
  double base_height = 0.0;       ///< m, its lower face above the torsion shaft axis
  double surface_1_height = 0.0;  ///< m, testing surface 1 above the torsion shaft axis
  double surface_spacing = 0.0;   ///< m between neighbouring surfaces
  int surfaces = 0;
  int holes = 8;  ///< testing holes per surface, evenly spaced from 0 deg

  double surface_height(int surface) const { return surface_1_height + (surface - 1) * surface_spacing; }
  double centre_height() const { return base_height + 0.5 * height; }
};

/// Machine parameters as built: what the tolerances act on.
struct BalancingAsBuilt {
  models::SpringPlate horizontal_1, horizontal_2, torsional;
  double lever = 0.0;
  double piece_centre_offset = 0.0;  ///< test piece's mass centre above the calibration rotor's (m)
};

struct BalancingModel : ModelHeader {    ///< file, name, title, source of the model file
  models::SpringPlate horizontal_plate;  ///< each of the two (k5 each)
  models::SpringPlate torsional_plate;   ///< k6, acting at the lever
  /// [torsional_plate] end_condition: how the plate's end attaches to the swinging support
  /// (models/spring_plate_machine.h: the rotational stiffness and sensor 2's share).
  models::TorsionPlateEnd torsional_end = models::TorsionPlateEnd::kGuided;
  double lever = 0.0;       ///< l (m)
  double board_mass = 0.0;  ///< translating only (M - m)
  double spindle_mass = 0.0, spindle_centre_height = 0.0, spindle_inertia = 0.0;
  double damping_ratio_x = 0.0, damping_ratio_theta = 0.0;
  double gravity = 0.0;              ///< 0 = Eq. 8 as printed (pendulum term off)
  BalancingRotor rotor;              ///< the standard (calibration) rotor R
  procedures::SensorConfig sensors;  ///< nominal; gain errors come from the tolerances
  procedures::BalancingRunConfig run;
  bool speed_compensation = true;    ///< estimates use the encoder's speed (w^2 scaling)
  double hard_bearing_factor = 3.0;  ///< omega_1 >= factor * omega
  double centre_offset = 0.0;        ///< [statics] rotor mass centre off the spindle axis (m)
  // Tolerances (SI).
  ScopedTolerance plate_thickness, plate_width, plate_length;  ///< each plate drawn separately (m)
  ScopedTolerance youngs_modulus;                              ///< relative, all plates alike (one strip)
  ScopedTolerance lever_error;                                 ///< m
  ScopedTolerance sensor_1_offset;                             ///< m, sensor 1's height error about the shaft axis
  ScopedTolerance piece_centre_height;                         ///< m, test piece vs calibration rotor
  ScopedTolerance speed;                                       ///< relative deviation of the run's speed
  ScopedTolerance gain_error_1, gain_error_2;                  ///< relative
  ScopedTolerance test_mass;                                   ///< relative error of a calibration/test mass
  ScopedTolerance hole_radius;                                 ///< m
  ScopedTolerance hole_angle;                                  ///< rad
  ScopedTolerance correction_mass;                             ///< relative error of a placed correction mass
  ScopedTolerance correction_angle;                            ///< rad
  ScopedTolerance rotor_residual_1, rotor_residual_2;          ///< kg m, magnitudes; angles uniform
};

/// Loads and validates; `overrides` replace values by dotted key. Throws ValidationError.
BalancingModel load_balancing_model(const std::string& path, const std::map<std::string, std::string>& overrides = {});

/// The nominal machine as built (no tolerances): plates and lever of the model.
BalancingAsBuilt nominal_as_built(const BalancingModel& m);

/// Stiffness k5 of the pair: the two horizontal plates in parallel, averaged (N/m each);
/// sensor 1 reads plate 1's own k5,1 (machine_params sets sensor_1_plate_stiffness).
double horizontal_stiffness(const BalancingAsBuilt& b);

/// The machine under the weight of the frame and `rotor` (standard gravity, whatever the
/// dynamic model's gravity switch):
///   horizontal plates: columns carrying P = M g / 2 each; buckling factor P_cr / P with
///     P_cr = pi^2 E I / L^2 (fixed-guided sway column), axial stress P / (w t), and the loss
///     of lateral stiffness 1 - k(P) / k(0) (beam-column, guided_column_lateral_stiffness);
///   torsional plate: the rotor's mass centre `centre_offset` off the spindle axis tilts the
///     swinging part by theta = m_R g e / (K_rot - m g H) (the inverted pendulum of mass m at
///     H softens it; K_rot = rotation_factor k6 l^2 by the end condition); bending stress
///     6 M_max / (w t^2), M_max the plate's largest moment (torsion_plate_max_moment);
///   pendulum margin K_rot / (m g H): below 1 the swinging part topples.
struct BalancingStatics {
  double buckling_factor = 0.0;   ///< min over the two horizontal plates
  double axial_stress = 0.0;      ///< Pa, horizontal plates (largest)
  double stiffness_loss = 0.0;    ///< fraction of k5 lost to the weight
  double tilt = 0.0;              ///< rad
  double torsional_stress = 0.0;  ///< Pa
  double pendulum_margin = 0.0;   ///< k6 l^2 / (m g H); infinite if H <= 0
};
BalancingStatics machine_statics(const BalancingModel& m, const BalancingAsBuilt& b, const BalancingRotor& rotor);

/// The 2-DOF machine carrying `rotor` whose mass centre is raised by `b.piece_centre_offset`.
/// With gravity on (m.gravity > 0), the pendulum term of Eq. 8 and the weight's softening of
/// the horizontal plates (P = M g / 2 each) are both in; with gravity 0 neither is.
models::SpringPlateMachineParams machine_params(const BalancingModel& m, const BalancingAsBuilt& b,
                                                const BalancingRotor& rotor);

}  // namespace poise::kinds::balancing_machine
