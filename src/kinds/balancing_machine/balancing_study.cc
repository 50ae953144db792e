#include "kinds/balancing_machine/balancing_study.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <fstream>

#include "core/units.h"
#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"
#include "kinds/balancing_machine/balancing_bench.h"
#include "kinds/balancing_machine/balancing_iso_tests.h"
#include "kinds/balancing_machine/balancing_sections.h"
#include "kinds/balancing_machine/balancing_slots.h"
#include "sampling/random_stream.h"

namespace poise::kinds::balancing_machine {
using namespace poise::engine;

namespace {

using cd = std::complex<double>;
using models::PlaneMass;
using units::kPi;

// ---- the tolerances and their draws --------------------------------------------------------

using namespace detail;

double plane_height(const BalancingModel& m, int surface) { return m.rotor.surface_height(surface); }

// The machine as built from the sample's draws: its plates and lever.
BalancingAsBuilt machine_as_built(const BalancingModel& model, const Draws& d) {
  BalancingAsBuilt b = nominal_as_built(model);
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
  return b;
}

// The bench's machines (as built with rotor R and with the test piece, and nominal), its
// sensors as built, the nominal speed and the correction planes.
void set_up_bench(Bench& bench, const BalancingAsBuilt& b, const Draws& d) {
  const BalancingModel& model = bench.model;
  bench.machine_r = machine_params(model, b, model.rotor);
  BalancingAsBuilt piece_built = b;
  piece_built.piece_centre_offset = d.value[kPiece];
  bench.machine_piece = machine_params(model, piece_built, model.rotor);
  bench.nominal = machine_params(model, nominal_as_built(model), model.rotor);
  models::validate(bench.machine_r);
  models::validate(bench.machine_piece);
  bench.sensors.gain_error_1 = d.value[kGain1];
  bench.sensors.gain_error_2 = d.value[kGain2];
  bench.sensors.sensor_1_offset += d.value[kSensor1];
  bench.omega_nominal = models::rpm_to_rad_per_s(model.run.speed_rpm);
  const BalancingSections& sections = balancing_sections(bench.cfg);
  bench.planes = {plane_height(model, sections.plane_1_surface), plane_height(model, sections.plane_2_surface)};
}

// The machine's own outputs: natural frequencies, and the statics of the plates.
void machine_outputs(const Bench& bench, const BalancingAsBuilt& b, std::vector<double>& outputs, std::size_t& o) {
  const BalancingModel& model = bench.model;
  const models::NaturalFrequencies nf = models::natural_frequencies(bench.machine_r);
  outputs[o++] = nf.omega_1 / (2 * kPi);
  outputs[o++] = nf.omega_2 / (2 * kPi);
  outputs[o++] = nf.omega_1 / bench.omega_nominal;
  const BalancingStatics st = machine_statics(model, b, model.rotor);
  outputs[o++] = st.buckling_factor;
  outputs[o++] = std::max(st.axial_stress, st.torsional_stress) / 1e6;
  outputs[o++] = st.tilt / 1e-6;
  outputs[o++] = 100.0 * st.stiffness_loss;
  outputs[o++] = st.pendulum_margin;
}

// Influence-coefficient calibration on rotor R (its residual unknown to the machine).
void calibrate_on_rotor_r(Bench& bench, const RotorR& r) {
  const BalancingSections& sections = balancing_sections(bench.cfg);
  const double m = sections.calibration_mass, radius = sections.calibration_radius;
  const Eigen::Vector2cd a0 = bench.measure(bench.machine_r, r.masses);
  const Eigen::Vector2cd a1 = bench.measure(bench.machine_r, with(r.masses, {bench.place(m, radius, 0.0, r.z1)}));
  const Eigen::Vector2cd a2 = bench.measure(bench.machine_r, with(r.masses, {bench.place(m, radius, 0.0, r.z2)}));
  bench.cal = procedures::calibrate_influence(a0, a1, m * radius, a2, m * radius);
  bench.calibrated = true;
}

// One experiment of the study, by its type.
void run_experiment(Bench& bench, const BalancingExperiment& x, const RotorR& r, std::vector<double>& outputs,
                    std::size_t& o) {
  if (x.type == "separation") {
    separation_test(bench, x, r, outputs, o);
  } else if (x.type == "umar") {
    umar_test(bench, x, r, outputs, o);
  } else if (x.type == "stability") {
    stability_test(bench, x, r, outputs, o);
  } else if (x.type == "urr") {
    urr_test(bench, x, r, outputs, o);
  } else if (x.type == "umar_iso") {
    umar_iso_test(bench, x, r, outputs, o);
  } else if (x.type == "calibration") {
    calibration_outputs(bench, outputs, o);
  } else {
    accuracy_test(bench, x, r, outputs, o);
  }
}

// ---- one sample's procedure context ---------------------------------------------------------

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
  for (const SlotSpec& slot : kSlots) {
    const ScopedTolerance& t = model_.*slot.tol;
    if (t.per_test) continue;
    x.push_back(slot.magnitude ? 0.0 : t.spec.dist.quantile(0.5) / t.spec.display_factor);
    if (slot.magnitude) x.push_back(0.0);
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
  long steps = 0, rhs = 0;
  try {
    // The machine as built.
    const BalancingAsBuilt b = machine_as_built(model_, d);
    Bench bench(model_, config_, d, noise, ws);
    set_up_bench(bench, b, d);
    const double z1 = bench.planes.height_1, z2 = bench.planes.height_2;
    // Rotor R's own residual unbalance in the two correction planes (radius 1 m: m r = U).
    const std::vector<PlaneMass> rotor_r{{d.value[kResidual1], 1.0, d.angle[kResidual1], z1},
                                         {d.value[kResidual2], 1.0, d.angle[kResidual2], z2}};
    const RotorR r{rotor_r, {unbalance_of(rotor_r[0]), unbalance_of(rotor_r[1])}, z1, z2};
    std::size_t o = 0;
    machine_outputs(bench, b, out.outputs, o);
    calibrate_on_rotor_r(bench, r);
    for (const auto& x : balancing_sections(config_).experiments) run_experiment(bench, x, r, out.outputs, o);
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
