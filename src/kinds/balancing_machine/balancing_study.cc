#include "kinds/balancing_machine/balancing_study.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <fstream>

#include "core/units.h"
#include "sampling/random_stream.h"
#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"
#include "kinds/balancing_machine/balancing_iso_tests.h"
#include "kinds/balancing_machine/balancing_sections.h"
#include "kinds/balancing_machine/balancing_slots.h"

namespace poise::kinds::balancing_machine {
using namespace poise::engine;
namespace detail {

// Draws of one sample: unit-scope values from the design point, test-scope ones from the
// sample's stream each time they are asked for (in a fixed order: deterministic).
class Draws {
 public:
  Draws(const BalancingModel& m, sampling::RandomStream& rs) : m_(m), rs_(rs) {}
  /// The sample's stream of test-scope draws (also the accuracy test's random angles).
  sampling::RandomStream& stream() { return rs_; }
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

}  // namespace detail

namespace {

using cd = std::complex<double>;
using models::PlaneMass;
using units::kPi;

// ---- the tolerances and their draws --------------------------------------------------------

using namespace detail;

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

// ---- one sample ------------------------------------------------------------------------------

void BalancingStudy::compute(std::size_t i, Workspace& ws, SampleResult& out) const {
  start_sample(i, out);
  sampling::RandomStream rs(seed_, sampling::StreamId::kProcedure, design_.stream_index(i));
  sampling::RandomStream noise(seed_, sampling::StreamId::kNoise, design_.stream_index(i, 1));
  Draws d(model_, rs);
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
    run_tests(d, noise, ws, out);
  } catch (const std::exception& e) {
    out.ok = false;
    out.message = e.what();
  }
}

std::vector<double> BalancingStudy::nominal_inputs() const {
  std::vector<double> x;
  for (std::size_t s = 0; s < kSlotCount; ++s) {
    const ScopedTolerance& t = model_.*kSlots[s].tol;
    if (t.per_test) continue;
    x.push_back(kSlots[s].magnitude ? 0.0 : t.spec.dist.quantile(0.5) / t.spec.display_factor);
    if (kSlots[s].magnitude) x.push_back(0.0);
  }
  return x;
}

void BalancingStudy::evaluate_point(std::size_t k, std::span<const double> inputs, std::span<double> outputs) const {
  // Point k's per-test draws and noise: those of sample k (its streams without the Saltelli layout).
  sampling::RandomStream rs(seed_, sampling::StreamId::kProcedure, k);
  sampling::RandomStream noise(seed_, sampling::StreamId::kNoise, k);
  Draws d(model_, rs);
  std::size_t col = 0;
  for (std::size_t s = 0; s < kSlotCount; ++s) {
    const ScopedTolerance& t = model_.*kSlots[s].tol;
    if (t.per_test) continue;
    d.unit[s] = true;
    d.value[s] = inputs[col++] * t.spec.display_factor;
    if (kSlots[s].magnitude) d.angle[s] = inputs[col++] * units::kRadPerDeg;
  }
  const auto ws = make_workspace();
  SampleResult r;
  r.outputs.assign(output_names().size(), NAN);
  run_tests(d, noise, *ws, r);
  if (!r.ok) throw Error(r.message);
  std::copy(r.outputs.begin(), r.outputs.end(), outputs.begin());
}

void BalancingStudy::run_tests(Draws& d, sampling::RandomStream& noise, Workspace& ws, SampleResult& out) const {
  sampling::RandomStream& rs = d.stream();
  long steps = 0, rhs = 0;
  try {
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


}  // namespace poise::kinds::balancing_machine
