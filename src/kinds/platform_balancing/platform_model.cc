#include "kinds/platform_balancing/platform_model.h"

#include <cmath>

#include "core/units.h"
#include "engine/study_files/model_overrides.h"
#include "model_files/gimbal_model.h"

namespace poise::kinds::platform_balancing {
using namespace poise::engine;
using namespace poise::model_files;
namespace {
using units::Dimension;

const Dimension kInertia{{2, 1, 0, 0, 0, 0}};             // kg m^2
const Dimension kStiffness{{0, 1, -2, 0, 0, 0}};          // N/m
const Dimension kDamping{{0, 1, -1, 0, 0, 0}};            // N s/m
const Dimension kRotDamping{{2, 1, -1, 0, -1, 0}};        // N m s/rad
const Dimension kRotStiffness{{2, 1, -2, 0, -1, 0}};      // N m/rad
const Dimension kAngularRate{{0, 0, -1, 0, 1, 0}};        // rad/s
const Dimension kTorquePerCurrent{{2, 1, -2, -1, 0, 0}};  // N m/A

PlatformGimbal read_gimbal(TomlReader& t) {
  PlatformGimbal g;
  g.mass = t.quantity("mass", units::kMass, positive);
  g.inertia = {t.quantity("inertia_x", kInertia, positive), t.quantity("inertia_y", kInertia, positive),
               t.quantity("inertia_z", kInertia, positive)};
  g.centroid = {t.quantity("centroid_x", units::kLength, {}, 0.0), t.quantity("centroid_y", units::kLength, {}, 0.0),
                t.quantity("centroid_z", units::kLength, {}, 0.0)};
  g.kt_nominal = t.quantity("kt_nominal", kTorquePerCurrent, positive);
  g.current_limit = t.quantity("current_limit", units::kCurrent, positive);
  auto& b = g.bearing;
  b.support_stiffness = t.quantity("support_stiffness", kStiffness, positive);
  b.support_damping = t.quantity("support_damping", kDamping, non_negative);
  b.viscous_friction = t.quantity("viscous_friction", kRotDamping, non_negative);
  b.coulomb_friction = t.quantity("coulomb_friction", units::kTorque, non_negative);
  b.torsion_stiffness = t.quantity("torsion_stiffness", kRotStiffness, non_negative);
  b.torsion_zero = t.quantity("torsion_zero", units::kAngle);
  g.counterweight_radius = t.quantity("counterweight_radius", units::kLength, positive);
  g.counterweight_plane = t.quantity("counterweight_plane", units::kLength);
  g.lock_angle = t.quantity("lock_angle", units::kAngle);
  t.accept_notes();
  return g;
}

}  // namespace

models::Platform PlatformModel::nominal_platform() const {
  models::Platform p;
  for (models::Axis a : models::kAllAxes) {
    const PlatformGimbal& g = gimbal(a);
    models::GimbalBody& b = p.body(a);
    b.mass = g.mass;
    b.first_moment = g.mass * g.centroid;
    b.inertia = g.inertia.asDiagonal();
  }
  return p;
}

models::GimbalAngles PlatformModel::lock_angles() const {
  return {gimbal(models::Axis::kOuter).lock_angle, gimbal(models::Axis::kMiddle).lock_angle,
          gimbal(models::Axis::kInner).lock_angle};
}

PlatformModel load_platform_model(const std::string& path, const std::map<std::string, std::string>& overrides) {
  auto [doc, ctx] = open_model_file(path, overrides);
  TomlReader root(doc, ctx);
  PlatformModel m;
  static_cast<ModelHeader&>(m) = read_model_header(root, "platform_three_gimbal");
  for (models::Axis a : models::kAllAxes) {
    TomlReader t = root.table(models::axis_name(a));
    m.gimbals[static_cast<std::size_t>(a)] = read_gimbal(t);
  }
  read_test_plan_tables(root, m.plan);
  if (root.has_or_schema("solver")) {
    const double smoothing = root.table("solver").quantity("coulomb_smoothing", kAngularRate, positive);
    for (auto& g : m.gimbals) g.bearing.coulomb_smoothing = smoothing;
  }
  {
    TomlReader t = root.table("stabilization");
    auto& s = m.stabilization;
    if (t.has("bandwidth")) {
      // Renamed: the PID's K_p = J w^2 made it a natural frequency, not the loop's bandwidth.
      t.error("bandwidth", describe_node(*t.raw().get("bandwidth")),
              "a renamed key: did you mean natural_frequency (the PD part's natural frequency w_n, "
              "K_p = J w_n^2; the open-loop crossover is about 1.47 w_n at damping 0.7), or loop = \"rate_pi\" "
              "with crossover (a true open-loop crossover)?");
    }
    const std::string loop = t.choice("loop", {"position_pid", "rate_pi"}, "position_pid");
    s.type = loop == "rate_pi" ? models::LoopType::kRatePi : models::LoopType::kPositionPid;
    if (t.schema_only()) {  // `poise keys`: each loop's own keys are required with that loop only
      t.ask("natural_frequency",
            "a frequency with its unit, e.g. \"40 Hz\": the PD part's natural frequency w_n "
            "(K_p = J w_n^2); required with loop = \"position_pid\" (the default)",
            "", false);
      t.ask("damping", "a positive damping ratio; required with loop = \"position_pid\" (the default)", "", false);
      t.ask("crossover",
            "a frequency with its unit, e.g. \"40 Hz\": the rate loop's open-loop crossover; "
            "required with loop = \"rate_pi\"",
            "", false);
    }
    if (t.schema_only() || s.type == models::LoopType::kPositionPid) {
      s.frequency_hz = t.quantity("natural_frequency", units::kFrequency, positive);
      s.damping = t.number("damping", [](double v) { return v > 0 ? "" : "a positive damping ratio"; });
    }
    if (t.schema_only() || s.type == models::LoopType::kRatePi) {
      s.frequency_hz = t.quantity("crossover", units::kFrequency, positive);
    }
    s.integral_ratio = t.number("integral_ratio", [](double v) { return v >= 0 ? "" : "a ratio >= 0"; });
    if (s.type == models::LoopType::kRatePi && !(s.integral_ratio > 0)) {
      t.error("integral_ratio", "0",
              "a ratio > 0 for loop = \"rate_pi\" (w_i = rho w_c; 0 leaves no position stiffness)");
    }
    t.accept_notes();
  }
  {
    TomlReader t = root.table("tolerances");
    for (models::Axis a : models::kAllAxes) {
      m.centroid[static_cast<std::size_t>(a)] =
          read_scoped_tolerance(t, std::string(models::axis_name(a)) + "_centroid", units::kLength, "mm");
    }
    m.kt_calibration = read_scoped_tolerance(t, "kt_calibration", units::kDimensionless, "");
    m.kt_drift = read_scoped_tolerance(t, "kt_drift", units::kDimensionless, "");
    m.lock_error = read_scoped_tolerance(t, "lock_error", units::kAngle, "arcmin");
    m.fixture_tilt = read_scoped_tolerance(t, "fixture_tilt", units::kAngle, "arcmin");
    m.turntable_zero = read_scoped_tolerance(t, "turntable_zero", units::kAngle, "deg");
    m.gimbal_zero = read_scoped_tolerance(t, "gimbal_zero", units::kAngle, "deg");
    m.counterweight_mass = read_scoped_tolerance(t, "counterweight_mass", units::kDimensionless, "");
    m.counterweight_radius = read_scoped_tolerance(t, "counterweight_radius", units::kLength, "mm");
    m.counterweight_angle = read_scoped_tolerance(t, "counterweight_angle", units::kAngle, "deg");
    m.counterweight_plane = read_scoped_tolerance(t, "counterweight_plane", units::kLength, "mm");
  }
  finish(doc, *ctx);
  // The test servo's inertia estimate is set per axis from the assembly (PlatformStudy).
  return m;
}

}  // namespace poise::kinds::platform_balancing
