#include "kinds/balancing_machine/balancing_study.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <fstream>

#include "core/units.h"
#include "sampling/random_stream.h"
#include "engine/report_plot.h"
#include "engine/result_io.h"
#include "kinds/balancing_machine/balancing_iso_tests.h"
#include "kinds/balancing_machine/balancing_sections.h"

namespace poise::studies {
namespace {

using cd = std::complex<double>;
using models::PlaneMass;
using units::kPi;

// ---- the tolerances and their draws --------------------------------------------------------

enum Slot : std::size_t {
  kThicknessH1, kThicknessH2, kThicknessT, kWidthH1, kWidthH2, kWidthT, kLengthH1, kLengthH2, kLengthT,
  kYoungs, kLever, kSensor1, kPiece, kGain1, kGain2, kResidual1, kResidual2,
  kSpeed, kTestMass, kHoleRadius, kHoleAngle, kCorrMass, kCorrAngle, kSlotCount
};

struct SlotSpec {
  const char* name;    // input column
  const char* key;     // tolerance key in the model file
  const ScopedTolerance BalancingModel::*tol;
  bool magnitude;      // a magnitude with a uniform angle (two design dimensions)
  bool hardware;       // must be scope "unit" (a property of the machine as built)
};

const SlotSpec kSlots[kSlotCount] = {
    {"horizontal_1_thickness", "plate_thickness", &BalancingModel::plate_thickness, false, true},
    {"horizontal_2_thickness", "plate_thickness", &BalancingModel::plate_thickness, false, true},
    {"torsional_thickness", "plate_thickness", &BalancingModel::plate_thickness, false, true},
    {"horizontal_1_width", "plate_width", &BalancingModel::plate_width, false, true},
    {"horizontal_2_width", "plate_width", &BalancingModel::plate_width, false, true},
    {"torsional_width", "plate_width", &BalancingModel::plate_width, false, true},
    {"horizontal_1_length", "plate_length", &BalancingModel::plate_length, false, true},
    {"horizontal_2_length", "plate_length", &BalancingModel::plate_length, false, true},
    {"torsional_length", "plate_length", &BalancingModel::plate_length, false, true},
    {"youngs_modulus", "youngs_modulus", &BalancingModel::youngs_modulus, false, true},
    {"lever", "lever", &BalancingModel::lever_error, false, true},
    {"sensor_1_offset", "sensor_1_offset", &BalancingModel::sensor_1_offset, false, true},
    {"piece_centre_height", "piece_centre_height", &BalancingModel::piece_centre_height, false, true},
    {"gain_error_1", "gain_error_1", &BalancingModel::gain_error_1, false, true},
    {"gain_error_2", "gain_error_2", &BalancingModel::gain_error_2, false, true},
    {"rotor_residual_1", "rotor_residual_1", &BalancingModel::rotor_residual_1, true, true},
    {"rotor_residual_2", "rotor_residual_2", &BalancingModel::rotor_residual_2, true, true},
    {"speed", "speed", &BalancingModel::speed, false, false},
    {"test_mass", "test_mass", &BalancingModel::test_mass, false, false},
    {"hole_radius", "hole_radius", &BalancingModel::hole_radius, false, false},
    {"hole_angle", "hole_angle", &BalancingModel::hole_angle, false, false},
    {"correction_mass", "correction_mass", &BalancingModel::correction_mass, false, false},
    {"correction_angle", "correction_angle", &BalancingModel::correction_angle, false, false},
};

std::string display_suffix(const ToleranceSpec& s) {
  if (s.display_unit.empty()) return "";
  std::string u = s.display_unit;
  for (auto& ch : u) {
    if (ch == '*') ch = '_';
  }
  return "_" + u;
}

// Draws of one sample: unit-scope values from the design point, test-scope ones from the
// sample's stream each time they are asked for (in a fixed order: deterministic).
class Draws {
 public:
  Draws(const BalancingModel& m, sampling::RandomStream& rs) : m_(m), rs_(rs) {}
  double value[kSlotCount]{};
  double angle[kSlotCount]{};
  bool unit[kSlotCount]{};
  /// The value for this use: the unit draw, or a fresh test-scope draw.
  double use(Slot s) {
    if (unit[s]) return value[s];
    const ToleranceSpec& t = (m_.*kSlots[s].tol).spec;
    return kSlots[s].magnitude ? t.dist.magnitude_quantile(rs_.uniform()) : t.dist.quantile(rs_.uniform());
  }

 private:
  const BalancingModel& m_;
  sampling::RandomStream& rs_;
};

double plane_height(const BalancingModel& m, int surface) { return m.rotor.surface_height(surface); }

// ---- one sample's procedure context ---------------------------------------------------------

struct Bench {
  const BalancingModel& model;
  const StudyConfig& cfg;
  Draws& draws;
  sampling::RandomStream& noise;
  procedures::BalancingWorkspace& ws;
  models::SpringPlateMachineParams machine_r;      // as built, rotor R
  models::SpringPlateMachineParams machine_piece;  // as built, the test piece
  models::SpringPlateMachineParams nominal;        // design values (closed form)
  procedures::SensorConfig sensors;
  procedures::CorrectionPlanes planes;
  double omega_nominal = 0.0;
  long steps = 0, rhs = 0;
  procedures::InfluenceCalibration cal;
  bool calibrated = false;

  /// A mass placed in a testing hole (with the hole's and the mass's errors).
  PlaneMass place(double mass, double radius, double angle, double height) {
    const double dm = draws.use(kTestMass), dr = draws.use(kHoleRadius), da = draws.use(kHoleAngle);
    return {mass * (1.0 + dm), radius + dr, angle + da, height};
  }
  /// A correction mass cancelling the estimated plane unbalance u (kg m) at radius r.
  PlaneMass correction(cd u, double radius, double height) {
    const double dm = draws.use(kCorrMass), da = draws.use(kCorrAngle);
    return {std::abs(u) / radius * (1.0 + dm), radius, std::arg(-u) + da, height};
  }
  /// One run; amplitudes referred to the nominal speed when the machine compensates.
  Eigen::Vector2cd measure(const models::SpringPlateMachineParams& machine, const std::vector<PlaneMass>& masses) {
    procedures::BalancingRunConfig run = model.run;
    run.speed_rpm *= 1.0 + draws.use(kSpeed);
    const procedures::BalancingMeasurement m =
        procedures::run_balancing_measurement(machine, masses, 0.0, run, sensors, noise, ws);
    steps += m.solver.steps;
    rhs += m.solver.rhs_evals;
    Eigen::Vector2cd a = m.amplitudes;
    if (model.speed_compensation) a *= (omega_nominal / m.omega) * (omega_nominal / m.omega);
    return a;
  }
  /// Plane unbalances (kg m) by the influence coefficients.
  Eigen::Vector2cd influence(const Eigen::Vector2cd& a) { return procedures::influence_estimate(cal, a); }
  /// Plane unbalances (kg m) by the corrected closed form on the design values.
  Eigen::Vector2cd closed_form(const Eigen::Vector2cd& a) {
    return procedures::closed_form_estimate(nominal, a, omega_nominal, 0.0, planes).planes;
  }
  Eigen::Vector2cd reading(const Eigen::Vector2cd& a) {
    return balancing_sections(cfg).estimator == "influence" ? influence(a) : closed_form(a);
  }
};

// The bench seen by the ISO tests: what the machine displays, and a test mass placed.
IsoBench iso_bench(Bench& bench, double z1, double z2) {
  IsoBench b;
  b.indicate = [&bench](const std::vector<PlaneMass>& m) { return bench.reading(bench.measure(bench.machine_r, m)); };
  b.place = [&bench](double mass, double r, double a, double z) { return bench.place(mass, r, a, z); };
  b.plane_1_height = z1;
  b.plane_2_height = z2;
  return b;
}

std::vector<PlaneMass> with(std::vector<PlaneMass> base, std::initializer_list<PlaneMass> extra) {
  base.insert(base.end(), extra.begin(), extra.end());
  return base;
}

cd unbalance_of(const PlaneMass& m) { return m.mass * m.radius * std::polar(1.0, m.angle); }

double rel_error(cd estimate, cd truth) { return std::abs(estimate - truth) / std::abs(truth); }

}  // namespace

// ---- construction ----------------------------------------------------------------------------

namespace {
std::size_t unit_dimensions(const BalancingModel& m) {
  std::size_t d = 0;
  for (const auto& s : kSlots) {
    if (!(m.*s.tol).per_test) d += s.magnitude ? 2 : 1;
  }
  return d;
}
}  // namespace

BalancingStudy::BalancingStudy(StudyConfig config, BalancingModel model, std::size_t samples, std::uint64_t seed)
    : config_(std::move(config)),
      model_(std::move(model)),
      samples_(samples),
      seed_(seed),
      dimension_(unit_dimensions(model_)),
      design_(make_design(config_, seed_, samples_, std::max<std::size_t>(dimension_, 1))) {
  std::vector<InputError> errors;
  auto refuse = [&](int line, const std::string& key, const std::string& value, const std::string& expected) {
    errors.emplace_back(SourceLocation{config_.file, line, 0}, key, value, expected);
  };
  const int surfaces = model_.rotor.surfaces;
  for (const auto& [key, s] : {std::pair{"procedure.plane_1_surface", balancing_sections(config_).plane_1_surface},
                               std::pair{"procedure.plane_2_surface", balancing_sections(config_).plane_2_surface}}) {
    if (s > surfaces) refuse(0, key, std::to_string(s), "a testing surface of the rotor, 1.." + std::to_string(surfaces));
  }
  for (std::size_t e = 0; e < balancing_sections(config_).experiments.size(); ++e) {
    const BalancingExperiment& x = balancing_sections(config_).experiments[e];
    if (x.type == "stability" && x.surface > surfaces) {
      refuse(0, "experiment[" + std::to_string(e) + "].surface", std::to_string(x.surface),
             "a testing surface of the rotor, 1.." + std::to_string(surfaces));
    }
  }
  for (std::size_t k = 0; k < kSlotCount; ++k) {
    const SlotSpec& s = kSlots[k];
    const bool first_of_key = k == 0 || kSlots[k - 1].tol != s.tol;  // plate keys cover three plates
    if (s.hardware && (model_.*s.tol).per_test && first_of_key) {
      errors.emplace_back(SourceLocation{model_.file, 0, 0}, std::string("tolerances.") + s.key + ".scope", "\"test\"",
                          "scope = \"unit\": a property of the machine or rotor as built, not of one run");
    }
  }
  // Inputs: unit-scope draws (a plate tolerance is drawn for each plate).
  for (const auto& s : kSlots) {
    const ScopedTolerance& t = model_.*s.tol;
    if (t.per_test) continue;
    input_names_.push_back(std::string(s.name) + display_suffix(t.spec));
    if (s.magnitude) input_names_.push_back(std::string(s.name) + "_angle_deg");
  }
  // Outputs.
  output_names_ = {"omega1_Hz",           "omega2_Hz",         "hard_bearing_ratio",
                   "static_buckling_ratio", "static_stress_MPa", "static_tilt_urad",
                   "weight_stiffness_loss_pct", "pendulum_margin_ratio"};
  for (const auto& x : balancing_sections(config_).experiments) {
    const std::string& n = x.name;
    if (x.type == "separation") {
      for (int s = 1; s <= surfaces; ++s) {
        output_names_.push_back(n + "_s" + std::to_string(s) + "_sensor1_mN");
        output_names_.push_back(n + "_s" + std::to_string(s) + "_sensor2_mN");
      }
      for (const char* o : {"_sensor1_spread_pct", "_sensor2_zero_height_mm", "_sensor2_linearity_pct"}) {
        output_names_.push_back(n + o);
      }
    } else if (x.type == "umar") {
      for (const char* o : {"_plane1_kgm", "_plane2_kgm", "_kgm", "_xmax1_g", "_xmin1_g", "_xmax2_g", "_xmin2_g",
                            "_true_residual1_kgm", "_true_residual2_kgm", "_max_reading_error_g"}) {
        output_names_.push_back(n + o);
      }
      for (int p = 1; p <= 2; ++p) {
        for (int k = 0; k < x.positions; ++k) {
          output_names_.push_back(n + "_p" + std::to_string(p) + "_k" + std::to_string(k) + "_g");
        }
      }
    } else if (x.type == "stability") {
      for (const char* o : {"_residual_gmm", "_plane1_max_dev_pct", "_plane2_max_dev_pct", "_pass_ratio"}) {
        output_names_.push_back(n + o);
      }
      for (int p = 1; p <= 2; ++p) {
        for (int k = 0; k < x.positions; ++k) {
          output_names_.push_back(n + "_p" + std::to_string(p) + "_k" + std::to_string(k) + "_ratio");
        }
      }
    } else if (x.type == "urr") {
      for (const char* o : {"_plane1_pct", "_plane2_pct", "_min_pct", "_pass_ratio", "_iso_plane1_pct", "_iso_plane2_pct",
                            "_iso_min_pct", "_iso_pass_ratio"}) {
        output_names_.push_back(n + o);
      }
    } else if (x.type == "umar_iso") {
      for (const char* o : {"_plane1_kgm", "_plane2_kgm", "_plane1_max_dev_g", "_plane2_max_dev_g", "_plane1_mean_g",
                            "_plane2_mean_g", "_pass_ratio"}) {
        output_names_.push_back(n + o);
      }
      for (int p = 1; p <= 2; ++p) {
        for (int k = 0; k < x.positions; ++k) output_names_.push_back(n + "_p" + std::to_string(p) + "_k" + std::to_string(k) + "_g");
      }
    } else {
      for (const char* o : {"_u_error_ic_gmm", "_v_error_ic_gmm", "_plane_error_ic_pct", "_u_error_cf_gmm",
                            "_v_error_cf_gmm", "_plane_error_cf_pct", "_interference_ic_per_mm",
                            "_interference_cf_per_mm", "_x_amplitude_um"}) {
        output_names_.push_back(n + o);
      }
    }
  }
  if (!errors.empty()) throw ValidationError(errors);
  warnings_ = input_warnings();
}

std::vector<std::string> BalancingStudy::input_warnings() const {
  std::vector<std::string> w;
  const BalancingRotor& r = model_.rotor;
  // Denser than lead (11,340 kg/m^3) is no solid rotor: mass or dimensions are likely wrong.
  const double density = r.mass / (kPi * 0.25 * r.diameter * r.diameter * r.height);
  if (density > 11340.0) {
    w.push_back(model_.file + ": key 'rotor.mass' = " + units::format(r.mass, "kg", 4) + ": the rotor (solid cylinder " +
                units::format(r.diameter, "mm", 4) + " x " + units::format(r.height, "mm", 4) + ") would have density " +
                units::format(density, "kg/m^3", 4) + ", above lead's 11340 kg/m^3; check the mass, diameter and height");
  }
  const double outer = 0.5 * r.diameter;
  auto radius_check = [&](const std::string& key, double radius) {
    if (radius > outer) {
      w.push_back(config_.file + ": key '" + key + "' = " + units::format(radius, "mm", 4) +
                  " lies outside the rotor (radius " + units::format(outer, "mm", 4) + " from rotor.diameter of " +
                  model_.file + "): a test mass there cannot be placed in a testing hole");
    }
  };
  radius_check("procedure.calibration_radius", balancing_sections(config_).calibration_radius);
  const auto& xs = balancing_sections(config_).experiments;
  for (std::size_t e = 0; e < xs.size(); ++e) radius_check("experiment[" + std::to_string(e) + "].radius", xs[e].radius);
  return w;
}

std::size_t BalancingStudy::runs_per_sample() const {
  std::size_t runs = 3;  // influence calibration
  for (const auto& x : balancing_sections(config_).experiments) {
    if (x.type == "separation") runs += 1 + static_cast<std::size_t>(model_.rotor.surfaces * x.positions);
    if (x.type == "umar") runs += 2 * static_cast<std::size_t>(x.positions);
    if (x.type == "stability") runs += static_cast<std::size_t>(x.positions) + (x.balance_first ? 1 : 0);
    if (x.type == "urr") runs += 3;  // today's run, and the ISO indication bare and loaded
    if (x.type == "umar_iso") runs += static_cast<std::size_t>(x.positions);
    if (x.type == "accuracy") runs += 2;
  }
  return runs;
}

std::unique_ptr<BalancingStudy::Workspace> BalancingStudy::make_workspace() const {
  return std::make_unique<Workspace>(model_.run.solver);
}

// ---- one sample ------------------------------------------------------------------------------

void BalancingStudy::compute(std::size_t i, Workspace& ws, SampleResult& out) const {
  out.index = i;
  out.ok = true;
  out.message.clear();
  out.inputs.assign(input_names_.size(), NAN);
  out.outputs.assign(output_names_.size(), NAN);
  out.solver_steps = out.rhs_evals = 0;
  sampling::RandomStream rs(seed_, sampling::StreamId::kProcedure, design_.stream_index(i));
  sampling::RandomStream noise(seed_, sampling::StreamId::kNoise, design_.stream_index(i));
  Draws d(model_, rs);
  long steps = 0, rhs = 0;
  try {
    std::vector<double> u(std::max<std::size_t>(dimension_, 1));
    design_.point(i, u);
    std::size_t k = 0, col = 0;
    for (std::size_t s = 0; s < kSlotCount; ++s) {
      const ScopedTolerance& t = model_.*kSlots[s].tol;
      if (t.per_test) continue;
      d.unit[s] = true;
      d.value[s] = kSlots[s].magnitude ? t.spec.dist.magnitude_quantile(u[k++]) : t.spec.dist.quantile(u[k++]);
      out.inputs[col++] = d.value[s] / t.spec.display_factor;
      if (kSlots[s].magnitude) {
        d.angle[s] = 2.0 * kPi * u[k++];
        out.inputs[col++] = d.angle[s] / units::kRadPerDeg;
      }
    }
    // The machine as built.
    BalancingAsBuilt b = nominal_as_built(model_);
    auto plate = [&](models::SpringPlate& p, Slot t, Slot w, Slot l) {
      p.thickness += d.value[t];
      p.width += d.value[w];
      p.length += d.value[l];
      p.youngs_modulus *= 1.0 + d.value[kYoungs];
    };
    plate(b.horizontal_1, kThicknessH1, kWidthH1, kLengthH1);
    plate(b.horizontal_2, kThicknessH2, kWidthH2, kLengthH2);
    plate(b.torsional, kThicknessT, kWidthT, kLengthT);
    b.lever += d.value[kLever];
    Bench bench{model_, config_, d, noise, ws, {}, {}, {}, model_.sensors, {}, 0.0, 0, 0, {}, false};
    bench.machine_r = machine_params(model_, b, model_.rotor);
    BalancingAsBuilt piece_built = b;
    piece_built.piece_centre_offset = d.value[kPiece];
    bench.machine_piece = machine_params(model_, piece_built, model_.rotor);
    bench.nominal = machine_params(model_, nominal_as_built(model_), model_.rotor);
    models::validate(bench.machine_r);
    models::validate(bench.machine_piece);
    bench.sensors.gain_error_1 = d.value[kGain1];
    bench.sensors.gain_error_2 = d.value[kGain2];
    bench.sensors.sensor_1_offset += d.value[kSensor1];
    bench.omega_nominal = models::rpm_to_rad_per_s(model_.run.speed_rpm);
    const double z1 = plane_height(model_, balancing_sections(config_).plane_1_surface), z2 = plane_height(model_, balancing_sections(config_).plane_2_surface);
    bench.planes = {z1, z2};
    // Rotor R's own residual unbalance in the two correction planes (radius 1 m: m r = U).
    const std::vector<PlaneMass> rotor_r{{d.value[kResidual1], 1.0, d.angle[kResidual1], z1},
                                         {d.value[kResidual2], 1.0, d.angle[kResidual2], z2}};
    const cd residual[2] = {unbalance_of(rotor_r[0]), unbalance_of(rotor_r[1])};

    std::size_t o = 0;
    const models::NaturalFrequencies nf = models::natural_frequencies(bench.machine_r);
    out.outputs[o++] = nf.omega_1 / (2 * kPi);
    out.outputs[o++] = nf.omega_2 / (2 * kPi);
    out.outputs[o++] = nf.omega_1 / bench.omega_nominal;
    const BalancingStatics st = machine_statics(model_, b, model_.rotor);
    out.outputs[o++] = st.buckling_factor;
    out.outputs[o++] = std::max(st.axial_stress, st.torsional_stress) / 1e6;
    out.outputs[o++] = st.tilt / 1e-6;
    out.outputs[o++] = 100.0 * st.stiffness_loss;
    out.outputs[o++] = st.pendulum_margin;

    // Influence-coefficient calibration on rotor R (its residual unknown to the machine).
    {
      const double m = balancing_sections(config_).calibration_mass, r = balancing_sections(config_).calibration_radius;
      const Eigen::Vector2cd a0 = bench.measure(bench.machine_r, rotor_r);
      const Eigen::Vector2cd a1 = bench.measure(bench.machine_r, with(rotor_r, {bench.place(m, r, 0.0, z1)}));
      const Eigen::Vector2cd a2 = bench.measure(bench.machine_r, with(rotor_r, {bench.place(m, r, 0.0, z2)}));
      bench.cal = procedures::calibrate_influence(a0, a1, m * r, a2, m * r);
      bench.calibrated = true;
    }

    for (const auto& x : balancing_sections(config_).experiments) {
      const double pos = x.positions;
      if (x.type == "separation") {
        const Eigen::Vector2cd bare = bench.measure(bench.machine_r, rotor_r);
        std::vector<double> h, s1, s2;
        for (int s = 1; s <= model_.rotor.surfaces; ++s) {
          const double z = model_.rotor.surface_height(s);
          double f1 = 0.0, f2 = 0.0;
          for (int hole = 0; hole < x.positions; ++hole) {
            const PlaneMass mass = bench.place(x.mass, x.radius, 2 * kPi * hole / pos, z);
            const Eigen::Vector2cd a = bench.measure(bench.machine_r, with(rotor_r, {mass})) - bare;
            f1 += std::abs(a(0)) / pos;
            f2 += std::abs(a(1)) / pos;
          }
          h.push_back(z);
          s1.push_back(f1);
          s2.push_back(f2);
          out.outputs[o++] = f1 * 1e3;
          out.outputs[o++] = f2 * 1e3;
        }
        const auto [mn, mx] = std::minmax_element(s1.begin(), s1.end());
        double mean1 = 0.0;
        for (double v : s1) mean1 += v / static_cast<double>(s1.size());
        out.outputs[o++] = (*mx - *mn) / mean1 * 100.0;
        // Sensor 2 against height: least-squares line F = a (z - z0).
        const double n = static_cast<double>(h.size());
        double sh = 0, sf = 0, shh = 0, shf = 0;
        for (std::size_t j = 0; j < h.size(); ++j) {
          sh += h[j];
          sf += s2[j];
          shh += h[j] * h[j];
          shf += h[j] * s2[j];
        }
        const double slope = (n * shf - sh * sf) / (n * shh - sh * sh);
        const double icpt = (sf - slope * sh) / n;
        out.outputs[o++] = -icpt / slope * 1e3;
        double worst = 0.0;
        for (std::size_t j = 0; j < h.size(); ++j) worst = std::max(worst, std::abs(s2[j] - (icpt + slope * h[j])));
        out.outputs[o++] = worst / *std::max_element(s2.begin(), s2.end()) * 100.0;
      } else if (x.type == "umar") {
        double umar[2], xmax[2], xmin[2], worst = 0.0;
        std::vector<double> readings;
        for (int p = 0; p < 2; ++p) {
          const double z = p == 0 ? z1 : z2;
          xmax[p] = -INFINITY;
          xmin[p] = INFINITY;
          for (int kpos = 0; kpos < x.positions; ++kpos) {
            const PlaneMass mass = bench.place(x.mass, x.radius, 2 * kPi * kpos / pos, z);
            const Eigen::Vector2cd plane = bench.reading(bench.measure(bench.machine_r, with(rotor_r, {mass})));
            const double reading = std::abs(plane(p)) / x.radius;  // kg of mass at radius r
            xmax[p] = std::max(xmax[p], reading);
            xmin[p] = std::min(xmin[p], reading);
            readings.push_back(reading * 1e3);
            worst = std::max(worst, std::abs(reading - std::abs(residual[p] + unbalance_of(mass)) / x.radius));
          }
          umar[p] = (xmax[p] - xmin[p]) * x.radius / 2.0;
        }
        for (double v : {umar[0], umar[1], umar[0] + umar[1], xmax[0] * 1e3, xmin[0] * 1e3, xmax[1] * 1e3,
                         xmin[1] * 1e3, std::abs(residual[0]), std::abs(residual[1]), worst * 1e3}) {
          out.outputs[o++] = v;
        }
        for (double v : readings) out.outputs[o++] = v;
      } else if (x.type == "stability") {
        std::vector<PlaneMass> rotor = rotor_r;
        if (x.balance_first) {
          const Eigen::Vector2cd est = bench.reading(bench.measure(bench.machine_r, rotor));
          rotor.push_back(bench.correction(est(0), x.radius, z1));
          rotor.push_back(bench.correction(est(1), x.radius, z2));
        }
        const cd left[2] = {residual[0] + (x.balance_first ? unbalance_of(rotor[2]) : 0.0),
                            residual[1] + (x.balance_first ? unbalance_of(rotor[3]) : 0.0)};
        out.outputs[o++] = std::max(std::abs(left[0]), std::abs(left[1])) * 1e6;
        const double zt = model_.rotor.surface_height(x.surface);
        std::vector<double> r1, r2;
        for (int kpos = 0; kpos < x.positions; ++kpos) {
          const PlaneMass mass = bench.place(x.mass, x.radius, 2 * kPi * kpos / pos, zt);
          const Eigen::Vector2cd plane = bench.reading(bench.measure(bench.machine_r, with(rotor, {mass})));
          r1.push_back(std::abs(plane(0)));
          r2.push_back(std::abs(plane(1)));
        }
        std::vector<double> ratios;
        double dev[2];
        bool pass = true;
        for (int p = 0; p < 2; ++p) {
          const auto& r = p == 0 ? r1 : r2;
          double mean = 0.0;
          for (double v : r) mean += v / pos;
          dev[p] = 0.0;
          for (double v : r) {
            ratios.push_back(v / mean);
            dev[p] = std::max(dev[p], std::abs(v / mean - 1.0));
          }
          pass = pass && dev[p] <= x.band;
        }
        out.outputs[o++] = dev[0] * 100.0;
        out.outputs[o++] = dev[1] * 100.0;
        out.outputs[o++] = pass ? 1.0 : 0.0;
        for (double v : ratios) out.outputs[o++] = v;
      } else if (x.type == "urr") {
        // ISO 21940-21 style: a known unbalance in both planes (at 0 and 90 deg), one
        // measuring run, one correction; URR = 1 - |after| / |before| per plane (true values).
        const PlaneMass t1 = bench.place(x.mass, x.radius, 0.0, z1);
        const PlaneMass t2 = bench.place(x.mass, x.radius, 0.5 * kPi, z2);
        const std::vector<PlaneMass> rotor = with(rotor_r, {t1, t2});
        const Eigen::Vector2cd est = bench.reading(bench.measure(bench.machine_r, rotor));
        const PlaneMass c1 = bench.correction(est(0), x.radius, z1), c2 = bench.correction(est(1), x.radius, z2);
        const cd before[2] = {residual[0] + unbalance_of(t1), residual[1] + unbalance_of(t2)};
        const cd after[2] = {before[0] + unbalance_of(c1), before[1] + unbalance_of(c2)};
        const double urr1 = 1.0 - std::abs(after[0]) / std::abs(before[0]);
        const double urr2 = 1.0 - std::abs(after[1]) / std::abs(before[1]);
        out.outputs[o++] = urr1 * 100.0;
        out.outputs[o++] = urr2 * 100.0;
        out.outputs[o++] = std::min(urr1, urr2) * 100.0;
        out.outputs[o++] = std::min(urr1, urr2) >= x.requirement ? 1.0 : 0.0;
        // ISO 21940-21: the indication of known test masses, no correction (balancing_iso_tests.h).
        IsoBench iso = iso_bench(bench, z1, z2);
        const IsoUrr ir = iso_urr(iso, rotor_r, x.mass, x.radius);
        out.outputs[o++] = ir.plane[0] * 100.0;
        out.outputs[o++] = ir.plane[1] * 100.0;
        out.outputs[o++] = std::min(ir.plane[0], ir.plane[1]) * 100.0;
        out.outputs[o++] = std::min(ir.plane[0], ir.plane[1]) >= x.requirement ? 1.0 : 0.0;
      } else if (x.type == "umar_iso") {
        IsoBench iso = iso_bench(bench, z1, z2);
        const TwoPlaneUmar t = two_plane_umar(iso, rotor_r, x.mass, x.radius, x.positions, x.plane_2_offset, x.claim);
        for (double v : {t.umar[0], t.umar[1], t.max_deviation[0] * 1e3, t.max_deviation[1] * 1e3, t.mean[0] * 1e3,
                         t.mean[1] * 1e3, t.pass ? 1.0 : 0.0}) {
          out.outputs[o++] = v;
        }
        for (int p = 0; p < 2; ++p) {
          for (double v : t.readings[p]) out.outputs[o++] = v * 1e3;
        }
      } else {  // accuracy
        // A test piece (mass centre offset from rotor R's) with plane unbalances of the given
        // size at random angles, measured on the machine calibrated with R.
        const double a1 = 2 * kPi * rs.uniform(), a2 = 2 * kPi * rs.uniform();
        const std::vector<PlaneMass> piece{{x.piece_unbalance, 1.0, a1, z1}, {x.piece_unbalance, 1.0, a2, z2}};
        const cd truth[2] = {unbalance_of(piece[0]), unbalance_of(piece[1])};
        const cd u_true = truth[0] + truth[1], v_true = truth[0] * z1 + truth[1] * z2;
        const Eigen::Vector2cd a = bench.measure(bench.machine_piece, piece);
        const Eigen::Vector2cd ic = bench.influence(a), cf = bench.closed_form(a);
        for (const Eigen::Vector2cd* e : {&ic, &cf}) {
          const Eigen::Vector2cd& est = *e;
          const cd u_est = est(0) + est(1), v_est = est(0) * z1 + est(1) * z2;
          out.outputs[o++] = std::abs(u_est - u_true) * 1e6;
          out.outputs[o++] = std::abs(v_est - v_true) / (z2 - z1) * 1e6;
          out.outputs[o++] = std::max(rel_error(est(0), truth[0]), rel_error(est(1), truth[1])) * 100.0;
        }
        // Couple-unbalance interference: a pure couple (equal masses 180 deg apart on the two
        // planes) added to the piece; the change of the indicated static unbalance per couple.
        const PlaneMass c1 = bench.place(x.mass, x.radius, 0.0, z1), c2 = bench.place(x.mass, x.radius, kPi, z2);
        const cd couple = unbalance_of(c1) * z1 + unbalance_of(c2) * z2;
        const Eigen::Vector2cd da = bench.measure(bench.machine_piece, with(piece, {c1, c2})) - a;
        const Eigen::Vector2cd dic = bench.influence(da), dcf = bench.closed_form(da);
        const cd applied_static = unbalance_of(c1) + unbalance_of(c2);  // ~0 (placement errors)
        out.outputs[o++] = std::abs(dic(0) + dic(1) - applied_static) / std::abs(couple) * 1e-3;
        out.outputs[o++] = std::abs(dcf(0) + dcf(1) - applied_static) / std::abs(couple) * 1e-3;
        // How far the horizontal plates move for a static unbalance of piece_unbalance (a
        // displacement pickup must resolve it): the piece's motion scaled by piece_unbalance / |U|.
        out.outputs[o++] = std::abs(a(0)) / (1.0 + d.value[kGain1]) / bench.machine_piece.sensor_1_plate_stiffness *
                           x.piece_unbalance / std::abs(u_true) * 1e6;
      }
    }
    steps = bench.steps;
    rhs = bench.rhs;
  } catch (const std::exception& e) {
    out.ok = false;
    out.message = e.what();
  }
  out.solver_steps = steps;
  out.rhs_evals = rhs;
}

nlohmann::json BalancingStudy::solver_json(const McResult& mc) const {
  return {{"integrator", "CVODE BDF"}, {"steps", mc.solver_steps}, {"rhs_evals", mc.rhs_evals},
          {"rtol", model_.run.solver.rtol}, {"atol_relative_to_response", model_.run.solver.atol},
          {"max_order", model_.run.solver.max_order}, {"runs_per_sample", runs_per_sample()}};
}

}  // namespace poise::studies
