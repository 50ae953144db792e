#include "kinds/platform_balancing/platform_study.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/units.h"
#include "kinds/platform_balancing/platform_study_config.h"
#include "models/seeker_los_chain.h"

namespace poise::kinds::platform_balancing {
using namespace poise::engine;
namespace {

using models::Axis;
using units::kPi;
using Slot = PlatformDraws::Slot;

// Noise of the axis tests: one stream per axis (not per order), so every order sees the
// same noise sequence on the same axis (common random numbers). Keys past the named
// StreamIds of random_stream.h.
constexpr std::uint64_t kAxisNoiseStream = 0x100;

const ScopedTolerance& tolerance_of(const PlatformModel& m, int slot) {
  switch (slot) {
    case Slot::kInnerCentroid: return m.centroid[0];
    case Slot::kMiddleCentroid: return m.centroid[1];
    case Slot::kOuterCentroid: return m.centroid[2];
    case Slot::kKtCalibration: return m.kt_calibration;
    case Slot::kKtDrift: return m.kt_drift;
    case Slot::kLockError: return m.lock_error;
    case Slot::kFixtureTilt: return m.fixture_tilt;
    case Slot::kTurntableZero: return m.turntable_zero;
    case Slot::kGimbalZero: return m.gimbal_zero;
    case Slot::kCounterweightMass: return m.counterweight_mass;
    case Slot::kCounterweightRadius: return m.counterweight_radius;
    case Slot::kCounterweightAngle: return m.counterweight_angle;
    default: return m.counterweight_plane;
  }
}

const char* slot_name(int slot) {
  static const char* kNames[] = {
      "inner_centroid",       "middle_centroid",     "outer_centroid",     "kt_calibration", "kt_drift",
      "lock_error",           "fixture_tilt",        "turntable_zero",     "gimbal_zero",    "counterweight_mass",
      "counterweight_radius", "counterweight_angle", "counterweight_plane"};
  return kNames[slot];
}

int instances(int slot) { return slot == Slot::kLockError ? 6 : 3; }

// The two gimbals locked during the test of axis t, in axis order.
int locked_gimbal(int test_axis, int j) {
  int n = 0;
  for (int b = 0; b < 3; ++b) {
    if (b == test_axis) continue;
    if (n++ == j) return b;
  }
  return -1;
}

std::string instance_label(int slot, int k) {
  if (slot <= Slot::kOuterCentroid) return std::string(1, "xyz"[k]);
  if (slot == Slot::kLockError) {
    return std::string(models::axis_name(static_cast<Axis>(locked_gimbal(k / 2, k % 2)))) + "_in_" +
           models::axis_name(static_cast<Axis>(k / 2)) + "_test";
  }
  return models::axis_name(static_cast<Axis>(k));
}

double& angle_of(models::GimbalAngles& q, int axis) { return axis == 0 ? q.gamma : (axis == 1 ? q.beta : q.alpha); }

std::string unit_suffix(const ScopedTolerance& t) {
  std::string u = t.spec.display_unit;
  for (auto& ch : u) {
    if (ch == '*') ch = '_';
  }
  return u.empty() ? "" : "_" + u;
}

std::vector<std::pair<int, int>> unit_slot_list(const PlatformModel& m) {
  std::vector<std::pair<int, int>> out;
  for (int s = 0; s < Slot::kNumSlots; ++s) {
    if (tolerance_of(m, s).per_test) continue;
    for (int k = 0; k < instances(s); ++k) out.emplace_back(s, k);
  }
  return out;
}

// Design dimensions: one per unit-scope draw, two for a tilt (magnitude and azimuth).
std::size_t unit_dimension(const std::vector<std::pair<int, int>>& slots) {
  std::size_t d = 0;
  for (const auto& sk : slots) d += sk.first == Slot::kFixtureTilt ? 2 : 1;
  return d;
}

// The per-sample outputs: each axis' largest initial torque, then per test order each axis'
// figures after the campaign and the LOS error over the carrier profile.
std::vector<OutputSpec> platform_outputs(const std::vector<std::string>& order_labels) {
  std::vector<OutputSpec> outputs;
  outputs.reserve(models::kAllAxes.size());
  for (Axis a : models::kAllAxes) {
    outputs.push_back({std::string("initial_") + models::axis_name(a) + "_torque_max_mNm", "mN*m",
                       std::string("largest unbalance torque on the ") + models::axis_name(a) +
                           " axis before balancing, over the gimbal-angle grid"});
  }
  static constexpr OutputDeclaration kAxisOutputs[] = {
      {"measured_mNm", "mN*m", "MT_s measured in the axis test"},
      {"residual_gmm", "g*mm",
       "residual first moment perpendicular to the axis after the campaign, at the lock angles"},
      {"residual_grid_max_gmm", "g*mm", "the same, greatest over the gimbal-angle grid"},
      {"torque_max_mNm", "mN*m", "largest residual unbalance torque over the grid, under gravity"},
      {"torque_rms_mNm", "mN*m", "RMS residual unbalance torque over the grid, under gravity"},
      {"torque_max_acc_mNm", "mN*m",
       "largest residual unbalance torque over the grid, under gravity plus the stated carrier acceleration"},
      {"torque_rms_acc_mNm", "mN*m",
       "RMS residual unbalance torque over the grid, under gravity plus the stated carrier acceleration"},
  };
  for (const auto& label : order_labels) {
    for (Axis a : models::kAllAxes) {
      append_outputs(outputs, label + "_" + models::axis_name(a) + "_", kAxisOutputs,
                     "order " + label + ", " + models::axis_name(a) + " axis: ");
    }
    outputs.push_back({label + "_los_max_arcsec", "arcsec",
                       "order " + label + ": peak LOS error over the carrier profile, worst grid point"});
    outputs.push_back({label + "_los_rms_arcsec", "arcsec",
                       "order " + label + ": RMS LOS error over the carrier profile, worst grid point"});
  }
  return outputs;
}

}  // namespace

PlatformStudy::PlatformStudy(StudyConfig config, PlatformModel model, std::size_t samples, std::uint64_t seed,
                             std::vector<double> shafting_los_arcsec, double pixel_arcsec)
    : config_(std::move(config)),
      model_(std::move(model)),
      samples_(samples),
      seed_(seed),
      shafting_(std::move(shafting_los_arcsec)),
      pixel_arcsec_(pixel_arcsec),
      unit_slots_(unit_slot_list(model_)),
      dimension_(unit_dimension(unit_slots_)),
      design_(make_design(config_, seed, samples, std::max<std::size_t>(dimension_, 1))) {
  shafting_sorted_ = shafting_;
  std::sort(shafting_sorted_.begin(), shafting_sorted_.end());
  for (const auto& [s, k] : unit_slots_) {
    const ScopedTolerance& t = tolerance_of(model_, s);
    const std::string tolerance = std::string("tolerances.") + slot_name(s);
    const std::string column = std::string(slot_name(s)) + "_" + instance_label(s, k);
    declare_input({column + unit_suffix(t), t.spec.display_unit.empty() ? "1" : t.spec.display_unit, "", tolerance});
    if (s == Slot::kFixtureTilt) declare_input({column + "_azimuth_deg", "deg", "its direction", tolerance});
  }
  declare_outputs(platform_outputs(platform_sections(config_).platform.order_labels));
  // Grid of gimbal angles.
  const PlatformStudySection& ps = platform_sections(config_).platform;
  for (double al : models::linspace(ps.outer_min, ps.outer_max, ps.outer_points)) {
    for (double be : models::linspace(ps.middle_min, ps.middle_max, ps.middle_points)) {
      for (double ga : models::linspace(ps.inner_min, ps.inner_max, ps.inner_points)) grid_.push_back({al, be, ga});
    }
  }
  // Nominal inertia about each axis at the lock angles: the test servo's estimate and the
  // stabilization loop's plant.
  const models::Platform nominal = model_.nominal_platform();
  for (Axis a : models::kAllAxes) {
    const int k = models::axis_component(a);
    const auto ia = static_cast<std::size_t>(a);
    axis_inertia_[ia] = models::outboard_assembly(nominal, a, model_.lock_angles()).inertia(k, k);
    loops_[ia] = model_.stabilization;
    loops_[ia].inertia = axis_inertia_[ia];
  }
  // Carrier profile and each loop's response to each acceleration component.
  models::CarrierProfile prof;
  prof.duration = ps.duration;
  prof.time_step = ps.time_step;
  prof.manoeuvre = {ps.manoeuvre[0], ps.manoeuvre[1], ps.manoeuvre[2]};
  prof.onset = ps.onset;
  prof.rise_time = ps.rise_time;
  for (const auto& v : ps.vibration)
    prof.vibration.push_back({{v.amplitude[0], v.amplitude[1], v.amplitude[2]}, v.frequency});
  const std::size_t n = prof.steps();
  profile_time_.resize(n);
  for (std::size_t t = 0; t < n; ++t) profile_time_[t] = static_cast<double>(t) * prof.time_step;
  // Each loop's response to each acceleration component, the profile evaluated at RK4's stages.
  for (std::size_t k = 0; k < 3; ++k) {
    for (std::size_t j = 0; j < 3; ++j) {
      const auto component = [&prof, j](double t) { return prof.acceleration(t)[static_cast<Eigen::Index>(j)]; };
      loop_response_[k][j] = models::loop_response(loops_[k], component, prof.time_step, n);
    }
  }
}

std::unique_ptr<PlatformStudy::Workspace> PlatformStudy::make_workspace() const {
  return std::make_unique<Workspace>(model_.plan.solver);
}

PlatformDraws PlatformStudy::draws(std::size_t i) const {
  PlatformDraws d;
  std::vector<double> u(std::max<std::size_t>(dimension_, 1));
  design_.point(i, u);
  sampling::RandomStream rs(seed_, sampling::StreamId::kProcedure, design_.stream_index(i));
  std::size_t k = 0;
  for (int s = 0; s < Slot::kNumSlots; ++s) {
    const ScopedTolerance& t = tolerance_of(model_, s);
    for (int j = 0; j < instances(s); ++j) {
      const double v = t.per_test ? rs.uniform() : u[k++];
      d.value[static_cast<std::size_t>(s)][static_cast<std::size_t>(j)] =
          s == Slot::kFixtureTilt ? t.spec.dist.magnitude_quantile(v) : t.spec.dist.quantile(v);
      if (s == Slot::kFixtureTilt)
        d.tilt_azimuth[static_cast<std::size_t>(j)] = 2.0 * kPi * (t.per_test ? rs.uniform() : u[k++]);
    }
  }
  return d;
}

models::Platform PlatformStudy::as_built(const PlatformDraws& d) const {
  models::Platform p = model_.nominal_platform();
  for (Axis a : models::kAllAxes) {
    const auto ia = static_cast<std::size_t>(a);
    const auto& off = d.value[Slot::kInnerCentroid + ia];
    p.body(a).first_moment =
        model_.gimbal(a).mass * (model_.gimbal(a).centroid + Eigen::Vector3d(off[0], off[1], off[2]));
  }
  return p;
}

CampaignResult PlatformStudy::run_campaign(std::size_t i, const models::Platform& built, const PlatformDraws& d,
                                           const std::array<int, 3>& order, Workspace& ws) const {
  CampaignResult r;
  r.platform = built;
  const models::GimbalAngles q_nom = model_.lock_angles();
  const double g0 = model_.plan.gravity;
  for (int ai : order) {
    const auto a = static_cast<Axis>(ai);
    const auto ia = static_cast<std::size_t>(ai);
    const PlatformGimbal& gim = model_.gimbal(a);
    // The other two gimbals locked with their locking errors.
    models::GimbalAngles q = q_nom;
    for (int j = 0; j < 2; ++j) {
      angle_of(q, locked_gimbal(ai, j)) += d.value[Slot::kLockError][ia * 2 + static_cast<std::size_t>(j)];
    }
    const models::GimbalBody asm_body = models::outboard_assembly(r.platform, a, q);
    const int k = models::axis_component(a), k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    const double sy = asm_body.first_moment[k1], sz = asm_body.first_moment[k2];
    const double e = std::hypot(sy, sz) / asm_body.mass;
    // The carrying gimbals' locking errors: the tested frame against the fixture.
    const Eigen::Matrix3d rel = models::base_from_gimbal(a, q_nom).transpose() * models::base_from_gimbal(a, q);
    const double tilt_y = rel(k1, k) + d.value[Slot::kFixtureTilt][ia] * std::cos(d.tilt_azimuth[ia]);
    const double tilt_z = rel(k2, k) + d.value[Slot::kFixtureTilt][ia] * std::sin(d.tilt_azimuth[ia]);
    const double about_axis = 0.5 * (rel(k2, k1) - rel(k1, k2));

    procedures::GimbalTruth truth;
    truth.disk = gim.bearing;
    truth.disk.mass = asm_body.mass;
    truth.disk.eccentricity = e;
    truth.disk.eccentricity_angle = std::atan2(sz, sy);
    truth.disk.inertia = asm_body.inertia(k, k) - asm_body.mass * e * e;
    truth.kt_true = gim.kt_nominal * (1.0 + d.value[Slot::kKtCalibration][ia]) * (1.0 + d.value[Slot::kKtDrift][ia]);
    truth.axis_tilt = std::atan2(std::hypot(tilt_y, tilt_z), rel(k, k));
    truth.axis_tilt_azimuth = std::atan2(tilt_z, tilt_y);
    truth.turntable_zero = d.value[Slot::kTurntableZero][ia] + std::asin(std::clamp(about_axis, -1.0, 1.0));

    procedures::TestPlan plan = model_.plan;
    plan.positions.clear();
    for (std::size_t p = 0; p < platform_sections(config_).platform.positions; ++p) {
      plan.positions.push_back(2.0 * kPi * static_cast<double>(p) /
                               static_cast<double>(platform_sections(config_).platform.positions));
    }
    plan.servo.kt_nominal = gim.kt_nominal;
    plan.servo.current_limit = gim.current_limit;
    plan.servo.inertia_estimate = axis_inertia_[ia];
    plan.oscillation.centre = d.value[Slot::kGimbalZero][ia];
    sampling::RandomStream noise(seed_, static_cast<sampling::StreamId>(kAxisNoiseStream + ia),
                                 design_.stream_index(i, 1));
    const procedures::MeasurementResult m = procedures::run_static_unbalance_procedure(plan, truth, noise, ws);
    r.solver_steps += m.solver.steps;
    r.rhs_evals += m.solver.rhs_evals;

    // Eq. 23 counterweight opposite the fitted unbalance, in the correction plane.
    AxisTestRecord& rec = r.tests[ia];
    rec.true_unbalance = std::hypot(sy, sz);
    rec.measured = m.fit.amplitude;
    rec.phase = m.fit.phase;
    for (const auto& p : m.positions) {
      rec.max_swing = std::max(rec.max_swing, p.max_abs_phi);
      rec.saturated = rec.saturated || p.saturated;
    }
    const double m_cw = procedures::counterweight_mass(m.fit.amplitude, gim.counterweight_radius, g0) *
                        (1.0 + d.value[Slot::kCounterweightMass][ia]);
    const double r_cw = gim.counterweight_radius + d.value[Slot::kCounterweightRadius][ia];
    const double a_cw = m.fit.phase + kPi + d.value[Slot::kCounterweightAngle][ia];
    Eigen::Vector3d pos;
    pos[k] = gim.counterweight_plane + d.value[Slot::kCounterweightPlane][ia];
    pos[k1] = r_cw * std::cos(a_cw);
    pos[k2] = r_cw * std::sin(a_cw);
    rec.counterweight_mass = m_cw;
    r.platform.body(a).add_point_mass(m_cw, pos);
  }
  return r;
}

PlatformStudy::Residual PlatformStudy::residual(const models::Platform& p) const {
  Residual out;
  const Eigen::Vector3d g(0.0, 0.0, -model_.plan.gravity);
  const auto& acc = platform_sections(config_).platform.acceleration;
  const Eigen::Vector3d f_acc = g - Eigen::Vector3d(acc[0], acc[1], acc[2]);
  for (Axis a : models::kAllAxes) {
    const int k = models::axis_component(a);
    const Eigen::Vector3d s = models::outboard_assembly(p, a, model_.lock_angles()).first_moment;
    out.perpendicular[static_cast<std::size_t>(a)] = std::hypot(s[(k + 1) % 3], s[(k + 2) % 3]);
  }
  // The same over the angle grid: the carried gimbals turn the outboard first moment.
  for (const auto& q : grid_) {
    for (Axis a : models::kAllAxes) {
      const int k = models::axis_component(a);
      const Eigen::Vector3d s = models::outboard_assembly(p, a, q).first_moment;
      auto& worst = out.perpendicular_grid_max[static_cast<std::size_t>(a)];
      worst = std::max(worst, std::hypot(s[(k + 1) % 3], s[(k + 2) % 3]));
    }
  }
  std::array<double, 3> sum_g{}, sum_a{};
  const std::size_t nt = profile_time_.size();
  for (const auto& q : grid_) {
    const auto c = models::torque_sensitivities(p, q);
    for (std::size_t k = 0; k < 3; ++k) {
      const double tg = c[k].dot(g), ta = c[k].dot(f_acc);
      out.max_g[k] = std::max(out.max_g[k], std::abs(tg));
      out.max_acc[k] = std::max(out.max_acc[k], std::abs(ta));
      sum_g[k] += tg * tg;
      sum_a[k] += ta * ta;
    }
    // LOS: th_k(t) = -c_k . Y_k(t); error vector sum_k th_k (axis_k x d).
    const Eigen::Vector3d d = models::line_of_sight(q);
    const Eigen::Matrix3d ro = models::rot_x(q.alpha), rm = ro * models::rot_z(q.beta);
    const std::array<Eigen::Vector3d, 3> v{rm.col(1).cross(d), ro.col(2).cross(d), Eigen::Vector3d::UnitX().cross(d)};
    std::array<std::array<Eigen::Vector3d, 3>, 3> w;  // [axis][component]
    for (std::size_t k = 0; k < 3; ++k) {
      for (std::size_t j = 0; j < 3; ++j) w[k][j] = -c[k][static_cast<Eigen::Index>(j)] * v[k];
    }
    // The constant gravity torque: taken out by a position integrator, held as c_k . g / K_p by
    // a loop without one (rate loop).
    Eigen::Vector3d held = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < 3; ++k) {
      if (!(loops_[k].ki() > 0)) held += c[k].dot(g) / loops_[k].kp() * v[k];
    }
    double peak = 0.0, sum2 = 0.0;
    for (std::size_t t = 0; t < nt; ++t) {
      Eigen::Vector3d err = held;
      for (std::size_t k = 0; k < 3; ++k) {
        for (std::size_t j = 0; j < 3; ++j) err += w[k][j] * loop_response_[k][j][t];
      }
      const double e2 = err.squaredNorm();
      peak = std::max(peak, e2);
      sum2 += e2;
    }
    out.los_max = std::max(out.los_max, std::sqrt(peak));
    out.los_rms = std::max(out.los_rms, std::sqrt(sum2 / static_cast<double>(nt)));
  }
  const auto ng = static_cast<double>(grid_.size());
  for (std::size_t k = 0; k < 3; ++k) {
    out.rms_g[k] = std::sqrt(sum_g[k] / ng);
    out.rms_acc[k] = std::sqrt(sum_a[k] / ng);
  }
  return out;
}

void PlatformStudy::compute(std::size_t i, Workspace& ws, SampleResult& out) const {
  start_sample(i, out);
  try {
    const PlatformDraws d = draws(i);
    std::size_t col = 0;
    for (const auto& [s, k] : unit_slots_) {
      const ScopedTolerance& t = tolerance_of(model_, s);
      out.inputs[col++] = d.value[static_cast<std::size_t>(s)][static_cast<std::size_t>(k)] / t.spec.display_factor;
      if (s == Slot::kFixtureTilt) out.inputs[col++] = d.tilt_azimuth[static_cast<std::size_t>(k)] / units::kRadPerDeg;
    }
    const models::Platform built = as_built(d);
    std::size_t o = 0;
    {
      const Residual r0 = residual(built);
      for (double v : r0.max_g) out.outputs[o++] = v * 1e3;
    }
    for (const auto& order : platform_sections(config_).platform.orders) {
      const CampaignResult c = run_campaign(i, built, d, order, ws);
      out.solver_steps += c.solver_steps;
      out.rhs_evals += c.rhs_evals;
      const Residual r = residual(c.platform);
      for (std::size_t k = 0; k < 3; ++k) {
        const double values[] = {c.tests[k].measured * 1e3, r.perpendicular[k] * 1e6, r.perpendicular_grid_max[k] * 1e6,
                                 r.max_g[k] * 1e3,          r.rms_g[k] * 1e3,         r.max_acc[k] * 1e3,
                                 r.rms_acc[k] * 1e3};
        for (double v : values) out.outputs[o++] = v;
      }
      out.outputs[o++] = r.los_max * units::kArcsecPerRad;
      out.outputs[o++] = r.los_rms * units::kArcsecPerRad;
    }
  } catch (const std::exception& e) {
    out.ok = false;
    out.message = e.what();
  }
}

std::vector<std::string> PlatformStudy::tolerance_keys() const {
  std::vector<std::string> keys;
  for (int s = 0; s < PlatformDraws::kNumSlots; ++s) {
    if (tolerance_of(model_, s).spec.tolerance > 0.0) keys.push_back(std::string("tolerances.") + slot_name(s));
  }
  return keys;
}

nlohmann::json PlatformStudy::solver_json(const McResult& mc) const {
  return {{"steps", mc.solver_steps},
          {"rhs_evals", mc.rhs_evals},
          {"rtol", model_.plan.solver.rtol},
          {"max_order", model_.plan.solver.max_order}};
}

}  // namespace poise::kinds::platform_balancing
