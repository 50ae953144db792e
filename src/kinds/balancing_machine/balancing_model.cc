#include "kinds/balancing_machine/balancing_model.h"

#include <cmath>

#include "core/units.h"
#include "engine/study_files/model_overrides.h"

namespace poise::kinds::balancing_machine {
using namespace poise::engine;
namespace {
using units::Dimension;

const Dimension kUnbalance{{1, 1, 0, 0, 0, 0}};  // kg m
const Dimension kInertia{{2, 1, 0, 0, 0, 0}};    // kg m^2
const Dimension kAngularRate{{0, 0, -1, 0, 1, 0}};

models::SpringPlate read_plate(TomlReader& t) {
  models::SpringPlate p;
  p.length = t.quantity("length", units::kLength, positive);
  p.width = t.quantity("width", units::kLength, positive);
  p.thickness = t.quantity("thickness", units::kLength, positive);
  p.youngs_modulus = t.quantity("youngs_modulus", units::kPressure, positive);
  return p;
}

std::string ratio_check(double v) { return v >= 0.0 && v < 1.0 ? "" : "a damping ratio in [0, 1)"; }

// [horizontal_plate] and [torsional_plate]: the spring plates, the lever and the torsional plate's end.
void read_plates(TomlReader& root, BalancingModel& m) {
  {
    TomlReader t = root.table("horizontal_plate");
    m.horizontal_plate = read_plate(t);
    t.accept_notes();
  }
  {
    TomlReader t = root.table("torsional_plate");
    m.torsional_plate = read_plate(t);
    m.lever = t.quantity("lever", units::kLength, positive);
    const std::string end =
        t.choice("end_condition", {"guided", "clamped_base_inboard", "clamped_base_outboard", "pinned"}, "guided");
    m.torsional_end = end == "clamped_base_inboard"    ? models::TorsionPlateEnd::kClampedBaseInboard
                      : end == "clamped_base_outboard" ? models::TorsionPlateEnd::kClampedBaseOutboard
                      : end == "pinned"                ? models::TorsionPlateEnd::kPinned
                                                       : models::TorsionPlateEnd::kGuided;
    t.accept_notes();
  }
}

// [frame] (masses, damping, gravity) and the optional [statics].
void read_frame(TomlReader& root, BalancingModel& m) {
  {
    TomlReader t = root.table("frame");
    m.board_mass = t.quantity("board_mass", units::kMass, non_negative);
    m.spindle_mass = t.quantity("spindle_mass", units::kMass, positive);
    m.spindle_centre_height = t.quantity("spindle_centre_height", units::kLength);
    m.spindle_inertia = t.quantity("spindle_inertia", kInertia, non_negative);
    m.damping_ratio_x = t.number("damping_ratio_x", ratio_check);
    m.damping_ratio_theta = t.number("damping_ratio_theta", ratio_check);
    m.gravity = t.quantity("gravity", units::kAcceleration, non_negative);
    if (m.damping_ratio_x <= 0.0 || m.damping_ratio_theta <= 0.0) {
      t.error(m.damping_ratio_x <= 0.0 ? "damping_ratio_x" : "damping_ratio_theta", "0",
              "a positive damping ratio (an undamped machine never reaches a steady state)");
    }
    t.accept_notes();
  }
  if (root.has_or_schema("statics")) {
    TomlReader t = root.table("statics");
    m.centre_offset = t.quantity("centre_offset", units::kLength, non_negative);
    t.accept_notes();
  }
}

// [rotor]: rotor R and its testing surfaces, which must lie within it.
void read_rotor(TomlReader& root, BalancingModel& m) {
  TomlReader t = root.table("rotor");
  auto& r = m.rotor;
  r.mass = t.quantity("mass", units::kMass, positive);
  r.diameter = t.quantity("diameter", units::kLength, positive);
  r.height = t.quantity("height", units::kLength, positive);
  r.base_height = t.quantity("base_height", units::kLength);
  r.surface_1_height = t.quantity("surface_1_height", units::kLength);
  r.surface_spacing = t.quantity("surface_spacing", units::kLength, positive);
  r.surfaces = static_cast<int>(t.integer("surfaces", 2, 1000));
  r.holes = static_cast<int>(t.integer("holes", 1, 360, 8));
  const double top = r.surface_height(r.surfaces);
  if (r.surface_1_height < r.base_height || top > r.base_height + r.height + 1e-12) {
    t.error("surfaces", std::to_string(r.surfaces),
            "testing surfaces within the rotor (surface 1 at " + units::format(r.surface_1_height, "mm", 4) +
                ", last at " + units::format(top, "mm", 4) + "; the rotor spans " +
                units::format(r.base_height, "mm", 4) + " to " + units::format(r.base_height + r.height, "mm", 4) +
                ")");
  }
  t.accept_notes();
}

// [sensors], [run] and [solver]: how a measuring run is made.
void read_run(TomlReader& root, BalancingModel& m) {
  {
    TomlReader t = root.table("sensors");
    auto& s = m.sensors;
    s.noise_rms = t.quantity("noise_rms", units::kForce, non_negative);
    s.sample_rate_hz = t.quantity("sample_rate", units::kFrequency, positive);
    s.sensor_1_offset = t.quantity("sensor_1_offset", units::kLength, {}, 0.0);
    t.accept_notes();
  }
  {
    TomlReader t = root.table("run");
    auto& r = m.run;
    r.speed_rpm = t.quantity("speed", kAngularRate, positive) * 60.0 / (2.0 * units::kPi);
    r.revolutions = static_cast<int>(t.integer("revolutions", 2, 100000));
    r.settle_time_constants = t.number("settle_time_constants", [](double v) { return v >= 0 ? "" : "a count >= 0"; });
    r.min_settle_revolutions = static_cast<int>(t.integer("min_settle_revolutions", 0, 100000, 2));
    m.speed_compensation = t.boolean("speed_compensation", true);
    m.hard_bearing_factor = t.number(
        "hard_bearing_factor", [](double v) { return v > 1 ? "" : "a factor > 1"; }, 3.0);
    t.accept_notes();
  }
  {
    TomlReader t = root.table("solver");
    auto& s = m.run.solver;
    s.rtol = t.number("rtol", [](double v) { return std::string(solvers::relative_tolerance_problem(v)); });
    s.atol = t.number("atol", [](double v) { return v > 0 && v < 1 ? "" : "0 < atol < 1 (relative to the response)"; });
    s.max_order = static_cast<int>(t.integer("max_order", 1, 5));
    s.atol_per_state.clear();
    // "integrated": CVODE through the start transient (the full model); "steady_state": the
    // exact steady state sampled with the same noise (procedures/balancing_measurement.h).
    m.run.response = t.choice("response", {"integrated", "steady_state"}, "integrated") == "steady_state"
                         ? procedures::BalancingResponse::kSteadyState
                         : procedures::BalancingResponse::kIntegrated;
    t.accept_notes();
  }
}

// [tolerances].
void read_tolerances(TomlReader& root, BalancingModel& m) {
  TomlReader t = root.table("tolerances");
  const auto L = units::kLength;
  const auto one = units::kDimensionless;
  m.plate_thickness = read_scoped_tolerance(t, "plate_thickness", L, "mm");
  m.plate_width = read_scoped_tolerance(t, "plate_width", L, "mm");
  m.plate_length = read_scoped_tolerance(t, "plate_length", L, "mm");
  m.youngs_modulus = read_scoped_tolerance(t, "youngs_modulus", one, "");
  m.lever_error = read_scoped_tolerance(t, "lever", L, "mm");
  m.sensor_1_offset = read_scoped_tolerance(t, "sensor_1_offset", L, "mm");
  m.piece_centre_height = read_scoped_tolerance(t, "piece_centre_height", L, "mm");
  m.speed = read_scoped_tolerance(t, "speed", one, "");
  m.gain_error_1 = read_scoped_tolerance(t, "gain_error_1", one, "");
  m.gain_error_2 = read_scoped_tolerance(t, "gain_error_2", one, "");
  m.test_mass = read_scoped_tolerance(t, "test_mass", one, "");
  m.hole_radius = read_scoped_tolerance(t, "hole_radius", L, "mm");
  m.hole_angle = read_scoped_tolerance(t, "hole_angle", units::kAngle, "deg");
  m.correction_mass = read_scoped_tolerance(t, "correction_mass", one, "");
  m.correction_angle = read_scoped_tolerance(t, "correction_angle", units::kAngle, "deg");
  m.rotor_residual_1 = read_scoped_tolerance(t, "rotor_residual_1", kUnbalance, "g*mm");
  m.rotor_residual_2 = read_scoped_tolerance(t, "rotor_residual_2", kUnbalance, "g*mm");
}

// Physics checks of the nominal machine (plates, frequencies), with the model's keys.
void check_physical_machine(const std::string& path, const BalancingModel& m) {
  try {
    const models::SpringPlateMachineParams p = machine_params(m, nominal_as_built(m), m.rotor);
    models::validate(p);
  } catch (const Error& e) {
    throw ValidationError(
        {InputError(SourceLocation{path, 0, 0}, "frame", "", std::string("a physical machine: ") + e.what())});
  }
}

}  // namespace

BalancingModel load_balancing_model(const std::string& path, const std::map<std::string, std::string>& overrides) {
  auto [doc, ctx] = open_model_file(path, overrides);
  TomlReader root(doc, ctx);
  BalancingModel m;
  static_cast<ModelHeader&>(m) = read_model_header(root, "balancing_machine");
  read_plates(root, m);
  read_frame(root, m);
  read_rotor(root, m);
  read_run(root, m);
  read_tolerances(root, m);
  finish(doc, *ctx);
  check_physical_machine(path, m);
  return m;
}

BalancingAsBuilt nominal_as_built(const BalancingModel& m) {
  BalancingAsBuilt b;
  b.horizontal_1 = b.horizontal_2 = m.horizontal_plate;
  b.torsional = m.torsional_plate;
  b.lever = m.lever;
  return b;
}

double horizontal_stiffness(const BalancingAsBuilt& b) {
  return 0.5 * (models::guided_plate_stiffness(b.horizontal_1) + models::guided_plate_stiffness(b.horizontal_2));
}

models::SpringPlateMachineParams machine_params(const BalancingModel& m, const BalancingAsBuilt& b,
                                                const BalancingRotor& rotor) {
  models::SpringPlateMachineParams p;
  const double m_r = rotor.mass, m_s = m.spindle_mass;
  const double z_r = rotor.centre_height() + b.piece_centre_offset, z_s = m.spindle_centre_height;
  const double radius = 0.5 * rotor.diameter;
  p.rotating_mass = m_r + m_s;
  p.mass_centre_height = (m_r * z_r + m_s * z_s) / p.rotating_mass;
  const double H = p.mass_centre_height;
  p.inertia = m.spindle_inertia + m_s * (z_s - H) * (z_s - H) +
              m_r * (3.0 * radius * radius + rotor.height * rotor.height) / 12.0 + m_r * (z_r - H) * (z_r - H);
  p.total_mass = p.rotating_mass + m.board_mass;
  p.lever = b.lever;
  p.horizontal_plate_stiffness = horizontal_stiffness(b);
  p.sensor_1_plate_stiffness = models::guided_plate_stiffness(b.horizontal_1);  // sensor 1 sits in plate 1
  if (m.gravity > 0.0) {
    const double load = 0.5 * (p.rotating_mass + m.board_mass) * m.gravity;
    p.sensor_1_plate_stiffness = models::guided_column_lateral_stiffness(b.horizontal_1, load);
    p.horizontal_plate_stiffness =
        0.5 * (p.sensor_1_plate_stiffness + models::guided_column_lateral_stiffness(b.horizontal_2, load));
  }
  p.torsional_plate_stiffness = models::guided_plate_stiffness(b.torsional);
  p.torsion_split = models::torsion_plate_split(m.torsional_end, b.torsional.length, b.lever);
  p.gravity = m.gravity;
  const Eigen::Matrix2d mq = models::mass_matrix(p), k = models::stiffness_matrix(p);
  p.damping_x = 2.0 * m.damping_ratio_x * std::sqrt(k(0, 0) * mq(0, 0));
  p.damping_theta = 2.0 * m.damping_ratio_theta * std::sqrt(std::max(k(1, 1), 0.0) * mq(1, 1));
  return p;
}

BalancingStatics machine_statics(const BalancingModel& m, const BalancingAsBuilt& b, const BalancingRotor& rotor) {
  constexpr double g = 9.80665;  // standard gravity: the weight is there even when Eq. 8 drops it
  const models::SpringPlateMachineParams p = machine_params(m, b, rotor);
  BalancingStatics s;
  const double load = 0.5 * p.total_mass * g;
  s.buckling_factor = std::min(models::guided_column_buckling_load(b.horizontal_1),
                               models::guided_column_buckling_load(b.horizontal_2)) /
                      load;
  s.axial_stress = std::max(load / (b.horizontal_1.width * b.horizontal_1.thickness),
                            load / (b.horizontal_2.width * b.horizontal_2.thickness));
  s.stiffness_loss =
      1.0 - (models::guided_column_lateral_stiffness(b.horizontal_1, load) +
             models::guided_column_lateral_stiffness(b.horizontal_2, load)) /
                (models::guided_plate_stiffness(b.horizontal_1) + models::guided_plate_stiffness(b.horizontal_2));
  const double k6 = models::guided_plate_stiffness(b.torsional);
  const double k_rot = p.torsion_split.rotation_factor * models::rotational_stiffness(k6, b.lever);
  const double topple = p.rotating_mass * g * p.mass_centre_height;
  s.pendulum_margin = topple > 0.0 ? k_rot / topple : INFINITY;
  s.tilt = rotor.mass * g * m.centre_offset / (k_rot - std::max(topple, 0.0));
  const double t = b.torsional.thickness;
  s.torsional_stress = 6.0 * models::torsion_plate_max_moment(b.torsional, m.torsional_end, b.lever, s.tilt) /
                       (b.torsional.width * t * t);
  return s;
}

}  // namespace poise::kinds::balancing_machine
