#include "model_files/gimbal_model.h"
#include "core/diagnostics.h"

#include <cmath>
#include <filesystem>
#include <iostream>

#include "core/format.h"
#include "core/units.h"
#include "engine/study_files/model_overrides.h"
#include "geometry/generators.h"
#include "geometry/mass_properties.h"

namespace poise::model_files {
using namespace poise::engine;
namespace {
using units::Dimension;

const Dimension kUnbalance{{1, 1, 0, 0, 0, 0}};           // kg m
const Dimension kInertia{{2, 1, 0, 0, 0, 0}};             // kg m^2
const Dimension kStiffness{{0, 1, -2, 0, 0, 0}};          // N/m
const Dimension kDamping{{0, 1, -1, 0, 0, 0}};            // N s/m
const Dimension kRotDamping{{2, 1, -1, 0, -1, 0}};        // N m s/rad
const Dimension kRotStiffness{{2, 1, -2, 0, -1, 0}};      // N m/rad
const Dimension kAngularRate{{0, 0, -1, 0, 1, 0}};        // rad/s
const Dimension kTorquePerCurrent{{2, 1, -2, -1, 0, 0}};  // N m/A

}  // namespace

namespace {

void read_servo_table(TomlReader& t, procedures::ServoConfig& s) {
  s.bandwidth_hz = t.quantity("bandwidth", units::kFrequency, positive);
  s.damping = t.number("damping", [](double v) { return v > 0 ? "" : "a positive damping ratio"; });
  s.integral_ratio = t.number("integral_ratio", [](double v) { return v >= 0 ? "" : "a ratio >= 0"; });
  t.accept_notes();
}

void read_oscillation_table(TomlReader& t, procedures::OscillationConfig& o) {
  o.rate_amplitude = t.quantity("rate_amplitude", kAngularRate, positive);
  o.period = t.quantity("period", units::kTime, positive);
  o.periods = static_cast<int>(t.integer("periods", 1, 1000));
  o.lead_in = t.quantity("lead_in", units::kTime, non_negative);
  o.settle_time = t.quantity("settle_time", units::kTime, non_negative);
  o.centre = t.quantity("centre", units::kAngle, {}, 0.0);
  // The test's stated range of |phi| (Yang 2015, Sec. 6.1: within +-3 deg): the plan must fit
  // in it, and a position whose swing leaves it fails its sample (gimbal_study.h).
  o.swing_range = t.quantity("swing_range", units::kAngle, positive, 3.0 * units::kRadPerDeg);
  const double swing = o.rate_amplitude * o.period / (2.0 * units::kPi);
  if (std::abs(o.centre) + swing > o.swing_range + 1e-12) {
    t.error("rate_amplitude", "",
            "an oscillation within the stated swing_range +-" + units::format(o.swing_range, "deg", 4) +
                " (|centre| + A T / 2 pi = " + units::format(std::abs(o.centre) + swing, "deg", 4) + ")");
  }
  t.accept_notes();
}

void read_acquisition_table(TomlReader& t, procedures::AcquisitionConfig& a) {
  a.rate_hz = t.quantity("rate", units::kFrequency, positive);
  a.noise_rms = t.quantity("noise_rms", units::kCurrent, non_negative);
  a.offset = t.quantity("offset", units::kCurrent);
  a.offset_drift = t.quantity("offset_drift", units::kCurrent, non_negative);
  a.offset_noise = t.quantity("offset_noise", units::kCurrent, non_negative);
  a.adc_bits = static_cast<int>(t.integer("adc_bits", 4, 32));
  a.adc_full_scale = t.quantity("adc_full_scale", units::kCurrent, positive);
  t.accept_notes();
}

void read_turntable_table(TomlReader& t, procedures::TestPlan& plan) {
  plan.positioning_error = t.quantity("positioning_error", units::kAngle, non_negative);
  plan.gravity = t.quantity("gravity", units::kAcceleration, positive);
  plan.move_time = t.quantity("move_time", units::kTime, non_negative, 5.0);
  t.accept_notes();
}

void read_solver_table(TomlReader& t, solvers::CvodeOptions& solver) {
  solver.rtol = t.number("rtol", [](double v) { return std::string(solvers::relative_tolerance_problem(v)); });
  const double atol_angle = t.quantity("atol_angle", units::kAngle, positive);
  const double atol_length = t.quantity("atol_length", units::kLength, positive);
  solver.max_order = static_cast<int>(t.integer("max_order", 1, 5));
  // phi, phidot, y, ydot, z, zdot, integral of the angle error
  solver.atol_per_state = {atol_angle,  10 * atol_angle,   atol_length,     1e3 * atol_length,
                           atol_length, 1e3 * atol_length, 0.1 * atol_angle};
  t.accept_notes();
}

}  // namespace

void read_test_plan_tables(TomlReader& root, procedures::TestPlan& plan) {
  {
    TomlReader t = root.table("servo");
    read_servo_table(t, plan.servo);
  }
  {
    TomlReader t = root.table("oscillation");
    read_oscillation_table(t, plan.oscillation);
  }
  {
    TomlReader t = root.table("acquisition");
    read_acquisition_table(t, plan.acquisition);
  }
  {
    TomlReader t = root.table("turntable");
    read_turntable_table(t, plan);
  }
  {
    TomlReader t = root.table("solver");
    read_solver_table(t, plan.solver);
  }
}

namespace {

// [rotor]: the disk, its supports and its friction; the support model into the plan.
void read_rotor_table(TomlReader& root, GimbalModel& m) {
  TomlReader t = root.table("rotor");
  auto& r = m.rotor;
  r.mass = t.quantity("mass", units::kMass, positive);
  r.inertia = t.quantity("inertia", kInertia, positive);
  r.support_stiffness = t.quantity("support_stiffness", kStiffness, positive);
  r.support_damping = t.quantity("support_damping", kDamping, non_negative);
  r.viscous_friction = t.quantity("viscous_friction", kRotDamping, non_negative);
  r.coulomb_friction = t.quantity("coulomb_friction", units::kTorque, non_negative);
  r.coulomb_smoothing = t.quantity("coulomb_smoothing", kAngularRate, positive);
  r.torsion_stiffness = t.quantity("torsion_stiffness", kRotStiffness, non_negative);
  r.torsion_zero = t.quantity("torsion_zero", units::kAngle);
  r.cogging_torque = t.quantity("cogging_torque", units::kTorque, non_negative, 0.0);
  r.cogging_order = static_cast<int>(t.integer("cogging_order", 0, 100000, 0));
  r.cogging_phase = t.quantity("cogging_phase", units::kAngle, {}, 0.0);
  // [[rotor.cogging]]: a cogging map, one table per order (what `poise diagnose-record` prints).
  for (auto& c : t.table_array("cogging")) {
    models::DiskRotorParams::CoggingHarmonic h;
    h.order = static_cast<int>(c.integer("order", 1, 100000));
    h.torque = c.quantity("torque", units::kTorque, non_negative);
    h.phase = c.quantity("phase", units::kAngle, {}, 0.0);
    r.cogging_map.push_back(h);
  }
  // "dynamic": the 7-state disk on elastic supports; "quasi_static": the supports follow
  // their static load (models/disk_rotor.h), valid with the support mode far above the servo.
  m.plan.supports = t.choice("supports", {"dynamic", "quasi_static"}, "dynamic") == "quasi_static"
                        ? procedures::Supports::kQuasiStatic
                        : procedures::Supports::kDynamic;
  t.accept_notes();
}

// [motor]: the torque constant and current limit into the servo.
void read_motor_table(TomlReader& root, GimbalModel& m) {
  TomlReader t = root.table("motor");
  m.plan.servo.kt_nominal = t.quantity("kt_nominal", kTorquePerCurrent, positive);
  m.plan.servo.current_limit = t.quantity("current_limit", units::kCurrent, positive);
  t.accept_notes();
}

// Quasi-static supports only with the support mode well above the servo bandwidth.
void check_quasi_static_supports(TomlReader& root, const GimbalModel& m) {
  if (m.plan.supports == procedures::Supports::kQuasiStatic && m.rotor.mass > 0 && m.rotor.support_stiffness > 0) {
    // The reduction drops terms of order (servo / support frequency)^2: 1% at a factor 10.
    const double f_support = std::sqrt(m.rotor.support_stiffness / m.rotor.mass) / (2.0 * units::kPi);
    if (f_support < 10.0 * m.plan.servo.bandwidth_hz) {
      root.table("rotor").error("supports", "\"quasi_static\"",
                                "\"dynamic\", or supports whose mode sqrt(support_stiffness / mass) / 2 pi = " +
                                    units::format(f_support, "Hz", 4) + " is at least 10 x the servo bandwidth (" +
                                    units::format(m.plan.servo.bandwidth_hz, "Hz", 4) + ")");
    }
  }
}

// [counterweight] and [test_error].
void read_counterweight_and_test_error(TomlReader& root, GimbalModel& m) {
  {
    TomlReader t = root.table("counterweight");
    m.counterweight_radius = t.quantity("radius", units::kLength, positive);
    m.counterweight_placement = t.choice("placement", {"disk_frame", "turntable"}, "disk_frame");
    t.accept_notes();
  }
  if (root.has_or_schema("test_error")) {
    TomlReader t = root.table("test_error");
    m.error_mechanism = t.choice("mechanism", {"scale_and_zero", "additive", "both"}, "scale_and_zero");
    t.accept_notes();
  }
}

// [plausibility] and [disturbances] (optional).
void read_plausibility_and_disturbances(TomlReader& root, GimbalModel& m) {
  if (root.has_or_schema("plausibility")) {
    TomlReader t = root.table("plausibility");
    auto& p = m.plausibility;
    p.stated = true;
    p.kt_temperature_coefficient_per_K = t.number("kt_temperature_coefficient_per_K", [](double v) {
      return v != 0.0 && std::abs(v) < 0.1
                 ? ""
                 : "a relative change of K_T per kelvin, nonzero and below 0.1 (NdFeB: -0.0012)";
    });
    p.magnet_temperature_swing_K = t.number("magnet_temperature_swing_K", [](double v) {
      return v >= 0.0 && v <= 200.0 ? "" : "kelvin from 0 to 200 (1 sigma between tests)";
    });
    p.zero_registration = t.quantity("zero_registration", units::kAngle, non_negative);
    p.unbalance_error = t.quantity("unbalance_error", kUnbalance, non_negative);
    p.notes = t.string("notes", "");
  }
  if (root.has_or_schema("disturbances")) {  // effects the test's model does not declare; off by default
    TomlReader t = root.table("disturbances");
    auto& d = m.disturbances;
    d.offset_drift_rate = t.quantity("offset_drift_rate", units::Dimension{{0, 0, -1, 1, 0, 0}}, {}, 0.0);
    d.harmonic2_torque = t.quantity("harmonic2_torque", units::kTorque, non_negative, 0.0);
    d.harmonic2_phase = t.quantity("harmonic2_phase", units::kAngle, {}, 0.0);
    d.direction_torque = t.quantity("direction_torque", units::kTorque, {}, 0.0);
    d.bump_position = static_cast<int>(t.integer("bump_position", -1, 100000, -1));
    d.bump_torque = t.quantity("bump_torque", units::kTorque, {}, 0.0);
    t.accept_notes();
  }
}

// [tolerances]; the error mechanism not in use keeps its tolerances at zero.
void read_tolerances_table(TomlReader& root, GimbalModel& m) {
  {
    TomlReader t = root.table("tolerances");
    m.residual_unbalance = read_scoped_tolerance(t, "residual_unbalance", kUnbalance, "g*mm");
    m.runout = read_scoped_tolerance(t, "runout", units::kLength, "um");
    m.clump_mass = read_scoped_tolerance(t, "clump_mass", units::kMass, "g");
    m.hole_radius = read_scoped_tolerance(t, "hole_radius", units::kLength, "mm");
    m.hole_angle = read_scoped_tolerance(t, "hole_angle", units::kAngle, "deg");
    m.kt_calibration = read_scoped_tolerance(t, "kt_calibration", units::kDimensionless, "");
    m.kt_drift = read_scoped_tolerance(t, "kt_drift", units::kDimensionless, "");
    m.turntable_zero = read_scoped_tolerance(t, "turntable_zero", units::kAngle, "deg");
    m.gimbal_zero = read_scoped_tolerance(t, "gimbal_zero", units::kAngle, "deg");
    m.axis_tilt = read_scoped_tolerance(t, "axis_tilt", units::kAngle, "arcmin");
    m.counterweight_mass = read_scoped_tolerance(t, "counterweight_mass", units::kDimensionless, "");
    m.counterweight_radius_error = read_scoped_tolerance(t, "counterweight_radius", units::kLength, "mm");
    m.counterweight_angle = read_scoped_tolerance(t, "counterweight_angle", units::kAngle, "deg");
    // The additive mechanism's tolerances: optional, per test, drawn only when it is in use.
    for (auto [key, tol] : {std::pair{"unbalance_error_along", &m.unbalance_error_along},
                            std::pair{"unbalance_error_across", &m.unbalance_error_across}}) {
      const bool needed = m.error_mechanism != "scale_and_zero";
      if (t.has_or_schema(key) || needed) {
        *tol = read_scoped_tolerance(t, key, kUnbalance, "g*mm");
        if (!tol->per_test && t.has(key)) {
          TomlReader tt = t.table(key);
          tt.error("scope", "\"unit\"", "\"test\": the additive error is drawn anew for each test");
        }
      }
    }
  }
  // The mechanism not in use: its tolerances are not drawn (fixed at 0, the draws stay aligned).
  if (m.error_mechanism == "additive") {
    m.kt_drift.spec = ToleranceSpec{};
    m.gimbal_zero.spec = ToleranceSpec{};
  }
  if (m.error_mechanism == "scale_and_zero") {
    m.unbalance_error_along = ScopedTolerance{};
    m.unbalance_error_across = ScopedTolerance{};
  }
}

// What [geometry] names: a disk model file and the rotor's parts, loaded after the file is
// finished.
struct GeometryInputs {
  std::string disk_model;  ///< resolved path, "" = off
  std::optional<UserParts> parts;
};

// The parts' nominal mass and inertia about the gimbal axis, within the rotor's own.
void check_parts_within_rotor(TomlReader& t, const UserParts& parts, GimbalModel& m) {
  std::vector<geometry::AssemblyPart> nominal;
  for (const UserPart& p : parts.parts) nominal.push_back(p.part);
  const geometry::MassProperties nom = geometry::as_built_assembly(nominal, {});
  const double j = nom.inertia(2, 2) + nom.mass * (nom.com.x() * nom.com.x() + nom.com.y() * nom.com.y());
  if (nom.mass > m.rotor.mass) {
    t.error("part", units::format(nom.mass, "g", 4) + " of parts",
            "parts within the rotor: [rotor] mass (" + units::format(m.rotor.mass, "g", 4) +
                ") is the whole rotor as designed, its parts included");
  } else if (j > m.rotor.inertia) {
    t.error("part", units::format(j, "kg*m^2", 4) + " about the gimbal axis",
            "parts within the rotor: [rotor] inertia (" + units::format(m.rotor.inertia, "kg*m^2", 4) +
                ") is the whole rotor as designed, its parts included");
  }
  m.disk_nominal_mass = nom.mass;
  m.disk_nominal_inertia = j;
}

// [geometry]: disk_model or [[geometry.part]] (one or the other).
GeometryInputs read_geometry_table(TomlReader& root, const std::string& path, GimbalModel& m) {
  GeometryInputs g;
  if (root.has_or_schema("geometry")) {
    TomlReader t = root.table("geometry");
    g.disk_model = t.string("disk_model", "");  // "" = off
    if (!g.disk_model.empty()) {
      const std::string resolved =
          (std::filesystem::path(path).parent_path() / g.disk_model).lexically_normal().string();
      std::error_code ec;  // a name too long for the file system is a missing file, not an exception
      if (!std::filesystem::is_regular_file(resolved, ec)) {
        t.error("disk_model", quote_value(g.disk_model),
                "\"\" (off) or an existing disk model file (looked for " + resolved + ")");
      }
      g.disk_model = resolved;
    }
    if (t.has_or_schema("part")) {
      const std::size_t errors_before = t.context().errors.size();
      g.parts = read_user_parts(t, std::filesystem::path(path).parent_path().string());
      if (!g.disk_model.empty() && !g.parts->parts.empty()) {
        t.error("disk_model", quote_value(t.string("disk_model", "")),
                "\"\" when the rotor is given as [[geometry.part]] (one or the other)");
      }
      if (g.parts->parts.empty()) g.parts.reset();
      if (g.parts && t.context().errors.size() == errors_before && !t.schema_only()) {
        check_parts_within_rotor(t, *g.parts, m);
      }
    }
    t.accept_notes();
  }
  return g;
}

// The parts' warnings, and the disk model's nominal mass and inertia.
void attach_geometry(GeometryInputs&& g, const std::string& path, GimbalModel& m) {
  if (g.parts) {
    for (const std::string& w : g.parts->warnings) diagnostics::warning(path + ": " + w);
    m.rotor_parts = std::move(g.parts);
  }
  if (!g.disk_model.empty()) {
    m.disk_geometry = load_disk_geometry_model(g.disk_model);
    m.disk_geometry->nominal.clumps.clear();
    const geometry::Moments mo = geometry::exact_moments(geometry::simulator_disk(m.disk_geometry->nominal));
    m.disk_nominal_mass = mo.mass;
    m.disk_nominal_inertia = mo.second(0, 0) + mo.second(1, 1);
  }
}

}  // namespace

GimbalModel load_gimbal_model(const std::string& path, const std::map<std::string, std::string>& overrides) {
  auto [doc, ctx] = open_model_file(path, overrides);
  TomlReader root(doc, ctx);
  GimbalModel m;
  static_cast<ModelHeader&>(m) = read_model_header(root, "gimbal_static_unbalance");
  read_rotor_table(root, m);
  read_motor_table(root, m);
  read_test_plan_tables(root, m.plan);
  if (root.has_or_schema("servo")) {
    m.plan.servo.inertia_estimate = root.table("servo").quantity("inertia_estimate", kInertia, positive);
  }
  check_quasi_static_supports(root, m);
  read_counterweight_and_test_error(root, m);
  read_plausibility_and_disturbances(root, m);
  read_tolerances_table(root, m);
  GeometryInputs g = read_geometry_table(root, path, m);
  finish(doc, *ctx);
  attach_geometry(std::move(g), path, m);
  return m;
}

std::vector<std::string> plausibility_warnings(const GimbalModel& m) {
  std::vector<std::string> w;
  const auto& p = m.plausibility;
  if (!p.stated) return w;
  const double s_k = m.kt_drift.spec.dist.stddev();
  const double coef = std::abs(p.kt_temperature_coefficient_per_K);
  const double k_limit = coef * p.magnet_temperature_swing_K;
  if (s_k > k_limit * (1.0 + 1e-9)) {
    w.push_back("tolerances.kt_drift: 1 sigma " + significant(100.0 * s_k, 3) + "% of K_T between tests needs a " +
                significant(s_k / coef, 3) + " K (1 sigma) magnet temperature swing at " +
                significant(100.0 * p.kt_temperature_coefficient_per_K, 3) + " %/K; [plausibility] states " +
                significant(p.magnet_temperature_swing_K, 3) + " K (" + significant(100.0 * k_limit, 3) +
                "% of K_T): past the physically plausible range");
  }
  const double s_z = m.gimbal_zero.spec.dist.stddev();
  if (s_z > p.zero_registration * (1.0 + 1e-9)) {
    w.push_back("tolerances.gimbal_zero: 1 sigma " + units::format(s_z, "deg", 3) + " is " +
                (p.zero_registration > 0 ? significant(s_z / p.zero_registration, 3) + " times" : "above") +
                " the zero registration the rig can do ([plausibility] zero_registration " +
                units::format(p.zero_registration, "deg", 3) + "): past the physically plausible range");
  }
  for (auto [name, tol] : {std::pair{"unbalance_error_along", &m.unbalance_error_along},
                           std::pair{"unbalance_error_across", &m.unbalance_error_across}}) {
    const double s = tol->spec.dist.stddev();
    if (s > p.unbalance_error * (1.0 + 1e-9)) {
      w.push_back(std::string("tolerances.") + name + ": 1 sigma " + units::format(s, "g*mm", 3) +
                  " is above what the additive error's stated sources give ([plausibility] unbalance_error " +
                  units::format(p.unbalance_error, "g*mm", 3) + "): past the physically plausible range");
    }
  }
  return w;
}

}  // namespace poise::model_files
