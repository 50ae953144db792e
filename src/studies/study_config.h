#pragma once
/// A study file (studies/*.toml): what to run, on which model, how to sample, what to
/// report. Strict like the model files: unknown keys, missing units and non-physical
/// values are refused with file, line, key, value and what was expected.
///
///   [study]     name, kind = "seeker_los", model (path relative to the study file),
///               title, notes
///   [sampling]  method = "sobol" | "lhs" | "monte_carlo", samples, seed,
///               replicate_size (optional), max_failure_share (optional, default 0.05)
///   [grid]      yaw_points, pitch_points (over the model's field of regard)
///   [requirement] los_error = "1 px" (or any angle)
///   [clearance] output = true, yaw_points, pitch_points (optional; geometry_study.h)
///   [overrides] "dotted.model.key" = "value"      (optional)
///   [[sweep]]   parameter = "dotted.model.key", values = [...], samples (optional)
///   kind = "gimbal_static_unbalance" replaces [grid]/[requirement] by test groups:
///   [[group]]   name, positions, placement, repeats, paper_rmse_torque, paper_rmse_angle
///   [[group.load]] mass, radius, angle, paper_torque, paper_angle
///   kind = "balancing_machine" (models/balancing_machine_*.toml) takes instead:
///   [procedure]  plane_1_surface, plane_2_surface (correction planes: testing surfaces),
///                estimator = "influence" | "closed_form" (what the machine displays),
///                calibration_mass, calibration_radius (influence-coefficient test masses)
///   [[experiment]] name (output prefix), type = "separation" | "umar" | "stability" | "urr" |
///                "accuracy", and per type: mass, radius, surface, positions, band,
///                piece_unbalance, requirement (see BalancingExperiment)
///   [paper]      output_name = value in the output's unit (the paper's figure, for the report)
///   kind = "geometry_mass_properties" (models/simulator_disk_*.toml) takes [mass_properties];
///   kind = "los_obstruction" (a seeker model with [geometry]) takes [grid], [beam], [clearance]
///   (see geometry_study.h)
///   kind = "platform_balancing" (models/platform_three_gimbal.toml) takes [platform] (see
///   platform_study_config.h): test orders, positions, angle grid, acceleration, profile, shafting
///   [output]    plots = true, block = 1024, contribution_samples = 4096  (optional)
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sampling/design.h"
#include "studies/platform_study_config.h"
#include "studies/geometry_study.h"

namespace poise::studies {

struct SweepSpec {
  std::string parameter;
  std::vector<std::string> values;
  std::size_t samples = 0;
};

/// A test mass of a gimbal loading test (Yang 2015, Tables 2-3).
struct GimbalLoad {
  double mass = 0.0;    ///< kg
  double radius = 0.0;  ///< m
  double angle = 0.0;   ///< rad
  std::optional<double> paper_torque;  ///< what the paper measured (N m), for the report
  std::optional<double> paper_angle;   ///< rad
};

/// A group of tests of one campaign: the same plan (number of positions), `repeats`
/// runs of each load; statistics (RMSE against the loads) are taken per group.
struct GimbalGroup {
  std::string name;
  std::size_t positions = 36;   ///< evenly spaced over 360 deg, from 0
  /// Order in which the turntable visits them: "sequential" (0, 10, 20, ... deg),
  /// "interleaved" (van der Corput order: 0, 180, 90, 270, ... deg, so that a drift in time
  /// does not follow the angle) or "back_and_forth" (the even positions going up, the odd
  /// ones coming back down, approached from the other side).
  std::string placement = "sequential";
  std::size_t repeats = 1;
  std::vector<GimbalLoad> loads;
  std::optional<double> paper_rmse_torque;  ///< N m
  std::optional<double> paper_rmse_angle;   ///< rad
};

/// One experiment of a balancing-machine study (Wang 2014 Sec. 5, ISO 21940-21 tests).
struct BalancingExperiment {
  std::string name;            ///< output prefix
  std::string type;            ///< separation | umar | stability | urr | accuracy
  double mass = 0.0;           ///< test mass (kg)
  double radius = 0.0;         ///< its radius (m)
  int surface = 0;             ///< stability: surface carrying the test mass
  int positions = 8;           ///< angular positions (holes) used, evenly spaced from 0 deg
  double band = 0.12;          ///< stability: readings within +-band of their mean
  bool balance_first = true;   ///< stability: correct the rotor with the machine first
  double piece_unbalance = 0;  ///< accuracy: plane unbalance of the test piece (kg m), random angles
  double requirement = 0.0;    ///< urr: required reduction ratio (fraction)
};

struct StudyConfig {
  std::string file;        ///< path of the study file
  std::string name, kind, title, notes;
  std::string model_path;  ///< resolved against the study file's folder
  sampling::SamplingMethod method = sampling::SamplingMethod::kSobol;
  std::size_t samples = 0;
  std::uint64_t seed = 0;
  /// [sampling] replicate_size: lhs and sobol in independent randomized replicates of this
  /// many points (sobol: a power of two), so that intervals come from their spread and
  /// --until can grow the run replicate by replicate; samples must be a multiple. 0 = off.
  std::size_t replicate_size = 0;
  /// [sampling] max_failure_share: the run stops with an error once more than this share
  /// of its samples has failed (default 0.05).
  double max_failure_share = 0.05;
  /// Not a file key: set by `poise sensitivity`, the base rows of the Saltelli layout
  /// (sampling/design.h) and whether the within-sample randomness is a group of its own.
  std::size_t saltelli_base = 0;
  bool saltelli_noise_group = false;
  std::size_t yaw_points = 13, pitch_points = 13;
  double requirement = 0.0;       ///< as written, in its unit's SI (rad or px)
  bool requirement_in_pixels = true;
  std::string requirement_text;
  std::map<std::string, std::string> overrides;
  std::vector<SweepSpec> sweeps;
  bool plots = true;
  std::size_t block = 1024;
  /// Contribution of each tolerance: the study re-run with that tolerance set to zero
  /// (same random numbers), with this many samples; 0 switches it off.
  std::size_t contribution_samples = 4096;
  std::vector<GimbalGroup> groups;  ///< kind = "gimbal_static_unbalance"
  // kind = "balancing_machine"
  int plane_1_surface = 0, plane_2_surface = 0;
  std::string estimator = "influence";
  double calibration_mass = 0.0, calibration_radius = 0.0;
  std::vector<BalancingExperiment> experiments;
  struct PaperValue {
    std::string output;  ///< an output name of the study
    double value = 0.0;  ///< in the output's unit
    int line = 0;        ///< in the study file
  };
  std::vector<PaperValue> paper;
  PlatformStudySection platform;  ///< kind = "platform_balancing" (platform_study_config.h)
  GeometryStudySpec geometry;  ///< kinds "geometry_mass_properties", "los_obstruction" (geometry_study.h)
};

/// The design of a study's samples: method, seed, replicates and Saltelli layout as configured.
sampling::Design make_design(const StudyConfig& cfg, std::uint64_t seed, std::size_t samples, std::size_t dimension);

/// Loads and validates a study file (not its model). Throws ValidationError.
StudyConfig load_study(const std::string& path);

/// Splits study-level keys off a set of overrides and applies them to `cfg`; returns the
/// rest (model keys). Study keys: "group.positions", "group.placement", "group.repeats"
/// (every [[group]]) and "group.<name>.<key>" (one group). They let an optimization vary
/// the test plan (e.g. a [[choice]] of the number of positions). Throws ValidationError
/// for an unknown group or key or a bad value.
std::map<std::string, std::string> apply_study_overrides(StudyConfig& cfg,
                                                         const std::map<std::string, std::string>& overrides);

}  // namespace poise::studies
