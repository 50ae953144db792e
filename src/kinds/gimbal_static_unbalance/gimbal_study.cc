#include "kinds/gimbal_static_unbalance/gimbal_study.h"

#include <cmath>

#include <algorithm>
#include <array>
#include "core/angles.h"
#include "core/error.h"
#include "core/format.h"
#include "core/units.h"
#include "geometry/generators.h"
#include "geometry/mass_properties.h"
#include "kinds/gimbal_static_unbalance/counterweight_residual.h"
#include "kinds/gimbal_static_unbalance/gimbal_sections.h"
#include "sampling/normal_stream.h"
#include "sampling/random_stream.h"

namespace poise::kinds::gimbal_static_unbalance {
using namespace poise::engine;
using namespace poise::model_files;

// The unit-scope draws, in design-dimension order: scalars take one dimension, vectors a
// magnitude and a uniform direction; and the disk's (or the parts') effects as built.
struct GimbalStudy::RigAsBuilt {
  double residual_unbalance = 0, residual_angle = 0, runout = 0, runout_angle = 0;
  double clump_mass = 0, hole_radius = 0, hole_angle = 0, kt_calibration = 0, kt_drift = 0;
  double turntable_zero = 0, gimbal_zero = 0, axis_tilt = 0, tilt_azimuth = 0;
  double cw_mass = 0, cw_radius = 0, cw_angle = 0;
  double disk_ux = 0, disk_uy = 0, disk_dm = 0, disk_dj = 0;  ///< kg m, kg m, kg, kg m^2
};

namespace {

using units::kPi;
using UnitDraws = GimbalStudy::RigAsBuilt;

struct Slot {
  const char* name;
  const ScopedTolerance GimbalModel::*tol;
  double UnitDraws::*value;
  double UnitDraws::*angle;  // nullptr for scalars
  bool magnitude;
};

const Slot kSlots[] = {
    {"residual_unbalance", &GimbalModel::residual_unbalance, &UnitDraws::residual_unbalance, &UnitDraws::residual_angle,
     true},
    {"runout", &GimbalModel::runout, &UnitDraws::runout, &UnitDraws::runout_angle, true},
    {"clump_mass", &GimbalModel::clump_mass, &UnitDraws::clump_mass, nullptr, false},
    {"hole_radius", &GimbalModel::hole_radius, &UnitDraws::hole_radius, nullptr, false},
    {"hole_angle", &GimbalModel::hole_angle, &UnitDraws::hole_angle, nullptr, false},
    {"kt_calibration", &GimbalModel::kt_calibration, &UnitDraws::kt_calibration, nullptr, false},
    {"kt_drift", &GimbalModel::kt_drift, &UnitDraws::kt_drift, nullptr, false},
    {"turntable_zero", &GimbalModel::turntable_zero, &UnitDraws::turntable_zero, nullptr, false},
    {"gimbal_zero", &GimbalModel::gimbal_zero, &UnitDraws::gimbal_zero, nullptr, false},
    {"axis_tilt", &GimbalModel::axis_tilt, &UnitDraws::axis_tilt, &UnitDraws::tilt_azimuth, true},
    {"counterweight_mass", &GimbalModel::counterweight_mass, &UnitDraws::cw_mass, nullptr, false},
    {"counterweight_radius", &GimbalModel::counterweight_radius_error, &UnitDraws::cw_radius, nullptr, false},
    {"counterweight_angle", &GimbalModel::counterweight_angle, &UnitDraws::cw_angle, nullptr, false},
};

using angles::wrap_pi;

std::size_t count_dims(const GimbalModel& m) {
  std::size_t d = 0;
  for (const auto& s : kSlots) {
    if (!(m.*s.tol).per_test) d += s.angle ? 2 : 1;
  }
  return d;
}

// One test's draws: the unit's, with the per-test tolerances drawn anew from `rs`.
UnitDraws draw_test(const GimbalModel& model, UnitDraws d, sampling::RandomStream& rs) {
  for (const auto& s : kSlots) {
    const ScopedTolerance& t = model.*s.tol;
    if (!t.per_test) continue;
    d.*s.value = s.magnitude ? t.spec.dist.magnitude_quantile(rs.uniform()) : t.spec.dist.quantile(rs.uniform());
    if (s.angle) d.*s.angle = 2.0 * kPi * rs.uniform();
  }
  return d;
}

// The rig as built for one test: what the procedure measures, and the unbalance (dx, dy)
// about the rotation centre (run-out included) that the counterweight acts against.
struct TestRig {
  procedures::GimbalTruth truth;
  double dx = 0.0, dy = 0.0;  ///< kg m
};

TestRig rig_for_test(const GimbalModel& model, const UnitDraws& d, const GimbalLoad& load) {
  const double clump = load.mass + d.clump_mass;
  const double radius = load.radius + d.hole_radius;
  const double angle = load.angle + d.hole_angle;
  const double m_total = model.rotor.mass + d.disk_dm + clump;
  const double ux = d.residual_unbalance * std::cos(d.residual_angle) + d.disk_ux + clump * radius * std::cos(angle);
  const double uy = d.residual_unbalance * std::sin(d.residual_angle) + d.disk_uy + clump * radius * std::sin(angle);
  TestRig rig;
  // Run-out: the rotation centre is off the geometric centre; it adds m r.
  rig.dx = ux + m_total * d.runout * std::cos(d.runout_angle);
  rig.dy = uy + m_total * d.runout * std::sin(d.runout_angle);
  procedures::GimbalTruth& truth = rig.truth;
  truth.disk = model.rotor;
  truth.disk.mass = m_total;
  truth.disk.inertia = model.rotor.inertia + d.disk_dj + clump * radius * radius;
  truth.disk.eccentricity = std::hypot(rig.dx, rig.dy) / m_total;
  truth.disk.eccentricity_angle = std::atan2(rig.dy, rig.dx);
  truth.kt_true = model.plan.servo.kt_nominal * (1.0 + d.kt_calibration) * (1.0 + d.kt_drift);
  truth.axis_tilt = d.axis_tilt;
  truth.axis_tilt_azimuth = d.tilt_azimuth;
  truth.turntable_zero = d.turntable_zero;
  truth.disturbances = model.disturbances;
  return rig;
}

// The estimated unbalance torque, the additive error included: amplitude (N m) and phase (rad).
struct UnbalanceEstimate {
  double amplitude = 0.0, phase = 0.0;
};

// Eq. 23 counterweight opposite the estimated unbalance, placed with its tolerances; the
// residual about the bearing axis, run-out included (counterweight_residual.h), in kg m.
double counterweight_residual(const GimbalModel& model, const std::string& placement, const UnitDraws& d,
                              const TestRig& rig, const UnbalanceEstimate& e, sampling::NormalStream& normal) {
  const double g0 = model.plan.gravity;
  const double m_cw = procedures::counterweight_mass(e.amplitude, model.counterweight_radius, g0) * (1.0 + d.cw_mass);
  const double r_cw = model.counterweight_radius + d.cw_radius;
  const double turn_back = placement == "turntable" ? model.plan.positioning_error * normal.next() : 0.0;
  const double a_cw =
      counterweight_disk_angle(placement, e.phase, d.gimbal_zero + d.turntable_zero, d.cw_angle + turn_back);
  const std::array<double, 2> runout{d.runout * std::cos(d.runout_angle), d.runout * std::sin(d.runout_angle)};
  const auto res = residual_about_bearing_axis({rig.dx, rig.dy}, runout, m_cw, r_cw, a_cw);
  return std::hypot(res[0], res[1]);
}

// A group's errors over its tests, against the loads (N m, rad), and what else it reports.
struct GroupErrors {
  double se_t = 0, se_a = 0, sum_t = 0, sum_a = 0, sum_mk = 0, max_res = 0, max_phi = 0, sum_fit_rmse = 0;
  std::size_t n = 0;

  // The group's outputs (outputs() order) into out.outputs from index o on.
  void write(const procedures::TestPlan& plan, SampleResult& out, std::size_t& o) const {
    const double nn = static_cast<double>(n);
    const double mean_t = sum_t / nn, mean_a = sum_a / nn;
    const double sd_t = n > 1 ? std::sqrt(std::max(0.0, (se_t - nn * mean_t * mean_t) / (nn - 1))) : 0.0;
    const double sd_a = n > 1 ? std::sqrt(std::max(0.0, (se_a - nn * mean_a * mean_a) / (nn - 1))) : 0.0;
    const double deg = units::kRadPerDeg;
    const double values[] = {std::sqrt(se_t / nn) * 1e3,
                             std::sqrt(se_a / nn) / deg,
                             mean_t * 1e3,
                             mean_a / deg,
                             sd_t * 1e3,
                             sd_a / deg,
                             sum_mk / nn * 1e3,
                             max_res * 1e6,
                             max_phi / deg,
                             sum_fit_rmse / nn * 1e3,
                             procedures::test_duration(plan) / 60.0};
    for (double v : values) out.outputs[o++] = v;
  }
};

}  // namespace

GimbalStudy::GimbalStudy(StudyConfig config, GimbalModel model, std::size_t samples, std::uint64_t seed)
    : config_(std::move(config)),
      model_(std::move(model)),
      samples_(samples),
      seed_(seed),
      dimension_(count_dims(model_)),
      disk_(model_.disk_geometry ? std::optional<DiskSampler>(std::in_place, *model_.disk_geometry) : std::nullopt),
      parts_(model_.rotor_parts ? std::optional<UserPartsSampler>(std::in_place, *model_.rotor_parts) : std::nullopt),
      design_(make_design(config_, seed, samples, std::max<std::size_t>(dimension_ + geometry_dimension(), 1))) {
  for (const auto& s : kSlots) {
    const ScopedTolerance& t = model_.*s.tol;
    if (t.per_test) continue;
    const std::string unit = t.spec.display_unit.empty() ? "1" : t.spec.display_unit;
    std::string u = unit;
    for (auto& ch : u) {
      if (ch == '*') ch = '_';
    }
    const std::string tolerance = std::string("tolerances.") + s.name;
    declare_input({std::string(s.name) + (unit == "1" ? "" : "_" + u), unit, "", tolerance});
    if (s.angle) declare_input({std::string(s.name) + "_angle_deg", "deg", "its direction", tolerance});
  }
  // The disk's (or the parts') drawn geometry, and what it gives the rotor (derived columns).
  static constexpr OutputDeclaration kDerived[] = {
      {"unbalance_gmm", "g*mm", "static unbalance of the drawn geometry"},
      {"unbalance_angle_deg", "deg", "its direction"},
      {"mass_g", "g", "mass of the drawn geometry"},
      {"inertia_kgm2", "kg*m^2", "moment of inertia about the axis under test"}};
  const auto geometry_inputs = [&](const std::vector<InputColumn>& columns, const std::string& column_prefix,
                                   const std::string& derived_prefix) {
    for (const auto& c : columns) declare_input({column_prefix + c.name, c.unit, "", ""});
    for (const auto& d : kDerived) declare_input({derived_prefix + d.name, d.unit, d.description, ""});
  };
  if (disk_) geometry_inputs(disk_->columns(), "disk_", "disk_");
  if (parts_) geometry_inputs(parts_->columns(), "part_", "parts_");
  static constexpr OutputDeclaration kGroupOutputs[] = {
      {"rmse_torque_mNm", "mN*m", "RMSE of the estimated MT_s against the loads over the group's tests"},
      {"rmse_angle_deg", "deg", "RMSE of the estimated unbalance angle b against the loads"},
      {"mean_torque_error_mNm", "mN*m", "mean error of MT_s over the group's tests"},
      {"mean_angle_error_deg", "deg", "mean error of b over the group's tests"},
      {"sd_torque_mNm", "mN*m", "standard deviation of the MT_s estimates over the group's tests"},
      {"sd_angle_deg", "deg", "standard deviation of the b estimates over the group's tests"},
      {"mean_offset_mNm", "mN*m", "mean fitted offset MK (Eq. 22)"},
      {"max_residual_gmm", "g*mm", "largest residual unbalance after the counterweight (Eq. 23)"},
      {"max_swing_deg", "deg", "largest swing |phi - phi_c| reached in the oscillation"},
      {"mean_fit_rmse_mNm", "mN*m", "RMS residual of the Eq. 22 sine fit"},
      {"test_time_min", "min", "duration of one test of the group"},
  };
  std::vector<OutputSpec> outputs;
  for (const auto& g : gimbal_sections(config_).groups) {
    append_outputs(outputs, g.name + "_", kGroupOutputs, "group " + g.name + ": ");
  }
  declare_outputs(std::move(outputs));
}

std::vector<std::string> GimbalStudy::tolerance_keys() const {
  std::vector<std::string> keys;
  for (const auto& s : kSlots) {
    if ((model_.*s.tol).spec.tolerance > 0.0) keys.push_back(std::string("tolerances.") + s.name);
  }
  return keys;
}

void GimbalStudy::check_positions(const procedures::MeasurementResult& m, const std::string& group, std::size_t test,
                                  double load_torque, double load_angle) const {
  const double deg = units::kRadPerDeg;
  const auto& o = model_.plan.oscillation;
  for (const auto& p : m.positions) {
    const std::string where =
        fmt::format("group {}, test {} (load {:.4g} mN*m at {:.4g} deg), turntable position {:.4g} deg", group, test,
                    load_torque * 1e3, load_angle / deg, p.theta_nominal / deg);
    if (p.saturated) {
      throw Error(fmt::format(
          "drive saturated: {}: the drive current reached its limit ({:.4g} A, {:.4g} mN*m at the nominal K_T) in "
          "the integration window, so Eq. 21's mean current is clipped and MT_s would come out low; the test "
          "needs a motor of more torque or a smaller load",
          where, model_.plan.servo.current_limit,
          model_.plan.servo.current_limit * model_.plan.servo.kt_nominal * 1e3));
    }
    if (std::abs(o.centre) + p.max_abs_phi > o.swing_range + 1e-12) {
      throw Error(fmt::format(
          "swing out of range: {}: the gimbal swung {:.4g} deg about its centre ({:.4g} deg), leaving the test's "
          "stated range +-{:.4g} deg ([oscillation] swing_range)",
          where, p.max_abs_phi / deg, o.centre / deg, o.swing_range / deg));
    }
  }
}

std::unique_ptr<GimbalStudy::Workspace> GimbalStudy::make_workspace() const {
  return std::make_unique<Workspace>(model_.plan.solver);
}

void GimbalStudy::compute(std::size_t i, Workspace& ws, SampleResult& out) const {
  start_sample(i, out);
  try {
    // Unit-scope draws from the design point; test-scope ones from the sample's stream.
    std::vector<double> u(std::max<std::size_t>(dimension_ + geometry_dimension(), 1));
    design_.point(i, u);
    RigAsBuilt unit;
    std::size_t k = 0, col = 0;
    for (const auto& s : kSlots) {
      const ScopedTolerance& t = model_.*s.tol;
      if (t.per_test) continue;
      unit.*s.value = s.magnitude ? t.spec.dist.magnitude_quantile(u[k++]) : t.spec.dist.quantile(u[k++]);
      out.inputs[col++] = unit.*s.value / t.spec.display_factor;
      if (s.angle) {
        unit.*s.angle = 2.0 * kPi * u[k++];
        out.inputs[col++] = unit.*s.angle / units::kRadPerDeg;
      }
    }
    // The disk as built: its unbalance about the gimbal axis and its mass and inertia.
    double& disk_ux = unit.disk_ux;
    double& disk_uy = unit.disk_uy;
    double& disk_dm = unit.disk_dm;
    double& disk_dj = unit.disk_dj;
    if (disk_) {
      std::vector<double> shown(disk_->dimension());
      const geometry::DiskSpec spec =
          disk_->draw(std::span<const double>(u).subspan(dimension_, disk_->dimension()), shown);
      for (double v : shown) out.inputs[col++] = v;
      const geometry::Moments mo = geometry::exact_moments(geometry::simulator_disk(spec));
      disk_ux = mo.first.x();
      disk_uy = mo.first.y();
      disk_dm = mo.mass - model_.disk_nominal_mass;
      disk_dj = mo.second(0, 0) + mo.second(1, 1) - model_.disk_nominal_inertia;
      out.inputs[col++] = std::hypot(disk_ux, disk_uy) * 1e6;
      out.inputs[col++] = std::atan2(disk_uy, disk_ux) / units::kRadPerDeg;
      out.inputs[col++] = mo.mass * 1e3;
      out.inputs[col++] = mo.second(0, 0) + mo.second(1, 1);
    }
    // The rotor's parts as built: the same four effects, about the gimbal axis (z).
    if (parts_) {
      std::vector<double> shown(parts_->dimension());
      const geometry::MassProperties mp =
          parts_->as_built(std::span<const double>(u).subspan(dimension_, parts_->dimension()), shown);
      for (double v : shown) out.inputs[col++] = v;
      const double j = mp.inertia(2, 2) + mp.mass * (mp.com.x() * mp.com.x() + mp.com.y() * mp.com.y());
      disk_ux = mp.mass * mp.com.x();
      disk_uy = mp.mass * mp.com.y();
      disk_dm = mp.mass - model_.disk_nominal_mass;
      disk_dj = j - model_.disk_nominal_inertia;
      out.inputs[col++] = std::hypot(disk_ux, disk_uy) * 1e6;
      out.inputs[col++] = std::atan2(disk_uy, disk_ux) / units::kRadPerDeg;
      out.inputs[col++] = mp.mass * 1e3;
      out.inputs[col++] = j;
    }
    run_campaign(design_.stream_index(i), unit, ws, out);
  } catch (const std::exception& e) {
    out.ok = false;
    out.message = e.what();
  }
}

void GimbalStudy::run_campaign(std::uint64_t stream, const RigAsBuilt& unit, Workspace& ws, SampleResult& out) const {
  sampling::RandomStream rs(seed_, sampling::StreamId::kProcedure, stream);
  sampling::NormalStream normal(&rs);
  const double g0 = model_.plan.gravity;
  std::size_t o = 0;
  for (const auto& grp : gimbal_sections(config_).groups) {
    procedures::TestPlan plan = model_.plan;
    procedures::set_positions(plan, grp.positions, procedures::parse_placement(grp.placement));
    const std::string placement =
        grp.counterweight_placement == "model" ? model_.counterweight_placement : grp.counterweight_placement;
    GroupErrors g;
    for (std::size_t r = 0; r < grp.repeats; ++r) {
      for (const auto& load : grp.loads) {
        const UnitDraws d = draw_test(model_, unit, rs);
        // The rig as built for this test.
        const TestRig rig = rig_for_test(model_, d, load);
        plan.oscillation.centre = model_.plan.oscillation.centre + d.gimbal_zero;
        // The additive mechanism's per-test error, along and across the estimate (kg m).
        double add_along = 0.0, add_across = 0.0;
        if (model_.error_mechanism != "scale_and_zero") {
          add_along = model_.unbalance_error_along.spec.dist.quantile(rs.uniform());
          add_across = model_.unbalance_error_across.spec.dist.quantile(rs.uniform());
        }
        const procedures::MeasurementResult m = procedures::run_static_unbalance_procedure(plan, rig.truth, rs, ws);
        out.solver_steps += m.solver.steps;
        out.rhs_evals += m.solver.rhs_evals;
        const double load_torque = load.mass * g0 * load.radius;  // what the test claims to load
        check_positions(m, grp.name, r * grp.loads.size() + static_cast<std::size_t>(&load - grp.loads.data()) + 1,
                        load_torque, load.angle);
        // The estimate with the additive error: a vector added to (MT_s, b).
        const double ex = m.fit.amplitude + add_along * g0, ey = add_across * g0;
        const UnbalanceEstimate e{std::hypot(ex, ey), m.fit.phase + std::atan2(ey, ex)};
        const double et = e.amplitude - load_torque;
        const double ea = wrap_pi(e.phase - load.angle);
        g.se_t += et * et;
        g.se_a += ea * ea;
        g.sum_t += et;
        g.sum_a += ea;
        g.sum_mk += m.fit.offset;
        g.sum_fit_rmse += m.fit.rmse;
        g.max_res = std::max(g.max_res, counterweight_residual(model_, placement, d, rig, e, normal));
        for (const auto& p : m.positions) g.max_phi = std::max(g.max_phi, p.max_abs_phi);
        ++g.n;
      }
    }
    g.write(plan, out, o);
  }
}

std::vector<double> GimbalStudy::nominal_inputs() const {
  std::vector<double> x;
  for (const auto& s : kSlots) {
    const ScopedTolerance& t = model_.*s.tol;
    if (t.per_test) continue;
    x.push_back(s.magnitude ? 0.0 : t.spec.dist.quantile(0.5) / t.spec.display_factor);
    if (s.angle) x.push_back(0.0);
  }
  return x;
}

void GimbalStudy::evaluate_point(std::size_t k, std::span<const double> inputs, std::span<double> outputs) const {
  RigAsBuilt rig;
  std::size_t col = 0;
  for (const auto& s : kSlots) {
    const ScopedTolerance& t = model_.*s.tol;
    if (t.per_test) continue;
    rig.*s.value = inputs[col++] * t.spec.display_factor;
    if (s.angle) rig.*s.angle = inputs[col++] * units::kRadPerDeg;
  }
  const auto ws = make_workspace();
  SampleResult r;
  r.outputs.assign(output_names().size(), NAN);
  run_campaign(k, rig, *ws, r);  // per-test draws and noise of sample k (stream k without the Saltelli layout)
  std::copy(r.outputs.begin(), r.outputs.end(), outputs.begin());
}

nlohmann::json GimbalStudy::solver_json(const McResult& mc) const {
  return {{"steps", mc.solver_steps},
          {"rhs_evals", mc.rhs_evals},
          {"rtol", model_.plan.solver.rtol},
          {"max_order", model_.plan.solver.max_order}};
}

}  // namespace poise::kinds::gimbal_static_unbalance
