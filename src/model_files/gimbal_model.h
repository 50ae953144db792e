#pragma once
/// The gimbal static-unbalance test rig (models/gimbal_simulator_*.toml): the disk rotor
/// of the axis under test, its instruments, the test plan, and every tolerance with its
/// distribution and scope:
///   scope = "unit"  drawn once per Monte Carlo sample (the hardware as built);
///   scope = "test"  drawn again for every test run (repeat or load) of that sample.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "engine/study_files/model_overrides.h"
#include "engine/study_files/tolerance_spec.h"
#include "engine/study_files/toml_reader.h"
#include "engine/study_files/user_parts.h"
#include "model_files/disk_geometry_model.h"
#include "procedures/static_unbalance_procedure.h"

namespace poise::model_files {
using engine::ModelHeader;
using engine::ScopedTolerance;
using engine::TomlReader;
using engine::UserParts;
using engine::ValidationError;

struct GimbalModel : ModelHeader {  ///< file, name, title, source of the model file
  models::DiskRotorParams rotor;    ///< eccentricity comes from the sampled unbalance
  procedures::TestPlan plan;        ///< positions are set per test group
  double counterweight_radius = 0;  ///< R of Eq. 23 (m)
  /// [counterweight] placement: "disk_frame" (at the fitted angle + 180 deg on the disk's own
  /// angle scale, registered to the gimbal zero: the zero errors go into the placement) or
  /// "turntable" (Yang 2015 Sec. 5.2: the turntable is turned back to the fitted angle and the
  /// counterweight set against gravity, so the gimbal- and turntable-zero errors cancel; the
  /// turntable's positioning error at that one position remains).
  std::string counterweight_placement = "disk_frame";
  /// [test_error] mechanism: which per-test error the rig has, "scale_and_zero" (kt_drift and
  /// gimbal_zero drawn per test), "additive" (unbalance_error_along / _across: a 2D random
  /// vector added to the estimated unbalance in each test, along and across it) or "both".
  /// The tolerances of the mechanism not chosen are not drawn.
  std::string error_mechanism = "scale_and_zero";
  procedures::Disturbances disturbances;  ///< undeclared effects, off unless [disturbances] sets them
  // Tolerances (SI). Magnitudes for vectors; their directions are uniform.
  ScopedTolerance residual_unbalance;          ///< simulator's own unbalance (kg m), random angle
  ScopedTolerance runout;                      ///< bearing run-out (m), random angle
  ScopedTolerance clump_mass;                  ///< deviation of the test mass (kg)
  ScopedTolerance hole_radius;                 ///< deviation of the hole radius (m)
  ScopedTolerance hole_angle;                  ///< deviation of the hole angle (rad)
  ScopedTolerance kt_calibration;              ///< K_T true / nominal - 1
  ScopedTolerance kt_drift;                    ///< further K_T change between tests
  ScopedTolerance turntable_zero;              ///< registration error of the turntable zero (rad)
  ScopedTolerance gimbal_zero;                 ///< registration error of the gimbal zero (rad)
  ScopedTolerance axis_tilt;                   ///< gimbal axis vs turntable axis (rad), random azimuth
  ScopedTolerance counterweight_mass;          ///< placement: mass deviation (relative)
  ScopedTolerance counterweight_radius_error;  ///< placement: radius deviation (m)
  ScopedTolerance counterweight_angle;         ///< placement: angle deviation (rad)
  ScopedTolerance unbalance_error_along;       ///< additive error along the estimated unbalance (kg m)
  ScopedTolerance unbalance_error_across;      ///< additive error across it (kg m)
  /// [plausibility] (optional): what the calibrated per-test tolerances may physically be.
  struct Plausibility {
    bool stated = false;
    double kt_temperature_coefficient_per_K = 0;  ///< K_T change per kelvin of magnet temperature (NdFeB ~ -0.0012)
    double magnet_temperature_swing_K = 0;        ///< 1 sigma magnet temperature change between tests (K)
    double zero_registration = 0;                 ///< 1 sigma of the gimbal-zero registration the rig can do (rad)
    double unbalance_error = 0;                   ///< 1 sigma of an additive unbalance error its sources give (kg m)
    std::string notes;
  } plausibility;
  /// [geometry] disk_model ("" = off, else a path relative to this file): the rotor's disk as a
  /// geometric part (models/simulator_disk_*.toml) drawn as built for every sample (unit
  /// scope). Its clumps are dropped: the test loads are the study's groups. The as-built
  /// disk's unbalance (its first moment about the gimbal axis, from the divergence theorem on
  /// its mesh) adds to residual_unbalance (then the rest of the rotor's), and its mass and
  /// inertia deviations from the nominal disk add to rotor.mass and rotor.inertia.
  std::optional<DiskGeometryModel> disk_geometry;
  /// [[geometry.part]] (engine/study_files/user_parts.h; instead of disk_model): the rotor's parts as
  /// meshes from CAD, z the gimbal axis, drawn as built for every sample (unit scope). As with
  /// disk_model, [rotor] mass and inertia are the rotor as designed (parts included): the
  /// as-built parts' unbalance about the gimbal axis, m (c_x, c_y), adds to residual_unbalance,
  /// and their mass and inertia about the axis, I_zz + m (c_x^2 + c_y^2), less the nominal
  /// assembly's, add to rotor.mass and rotor.inertia.
  std::optional<UserParts> rotor_parts;
  double disk_nominal_mass = 0.0;     ///< kg, the nominal disk without clumps (or the nominal parts)
  double disk_nominal_inertia = 0.0;  ///< kg m^2, about the gimbal axis
};

/// Reads the test-plan tables the gimbal and platform models share into `plan`: [servo]
/// bandwidth, damping, integral_ratio; [oscillation] rate_amplitude, period, periods, lead_in,
/// settle_time, centre (optional, 0; |centre| + A T / 2 pi within +-3 deg); [acquisition] rate,
/// noise_rms, offset, offset_drift, offset_noise, adc_bits, adc_full_scale; [turntable]
/// positioning_error, gravity, move_time (optional, 5 s); [solver] rtol, atol_angle,
/// atol_length, max_order (absolute tolerances per state of the disk rotor). A model reads its
/// own further keys of these tables itself.
void read_test_plan_tables(TomlReader& root, procedures::TestPlan& plan);

/// Warnings for calibrated tolerances past their physically plausible ranges ([plausibility]):
/// kt_drift's 1 sigma above |coefficient| x temperature swing, gimbal_zero's above the zero
/// registration, unbalance_error_along / _across above the additive error's sources. Empty
/// when [plausibility] is absent or every tolerance is inside; only the mechanism in use counts.
std::vector<std::string> plausibility_warnings(const GimbalModel& m);

/// Loads and validates; `overrides` replace values by dotted key. Throws ValidationError.
GimbalModel load_gimbal_model(const std::string& path, const std::map<std::string, std::string>& overrides = {});

}  // namespace poise::model_files
