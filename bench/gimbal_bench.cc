/// Benchmarks of one simulated static-unbalance measurement (Google Benchmark 1.7.1).
///
///   BM_Measurement36/rate:R  procedures::run_static_unbalance_procedure with 36 turntable positions
///     (each: settle, lead-in, 2 x 4 s oscillation of the full nonlinear disk rotor under its
///     PID servo, CVODE BDF2), current sampled at R Hz, then the sine fit. R = 500 (the
///     model's rate) and 50: the difference is the acquisition loop's share (per-sample
///     interpolation, reference, ADC). Target: <= 50 ms per measurement per core.
///   BM_Measurement18/rate:R  the same with 18 positions.
///   BM_Measurement36By/quasi_static:Q/loose:L/max_order:K  the 36-point measurement with the
///     model's acquisition (noise drawn in distribution), supports dynamic (Q = 0) or
///     quasi-static (Q = 1), tolerances L times the model's, BDF order limit K (0 = model's);
///     counters tol_torque_rel (this rotor and seed) and worst_torque_rel (the largest over the
///     accuracy sweep: 4 rotors x 3 noise seeds), each |MT_s - MT_s(reference)| / this rig's
///     load, and worst_offset_rel the same of the fitted offset MK; the reference from the
///     dynamic model at fixed tight tolerances (tight_plan).
///     bench/baselines/compare.py compares these with bench/baselines/gimbal_scipy.py --sweep
///     (LSODA, the same sweep), each at the loosest setting whose worst error is within 1e-4.
///     Target: >= 50x per core.
/// Rig: models/gimbal_simulator_yang2015.toml (load_gimbal_model; found via $POISE_SOURCE_DIR
/// or bench/..) with its solver settings, noise and positioning error (fixed seed); load
/// 25.81 g at r = 51 mm, 45.5 deg (12.91 mN*m); nominal K_T, no tilt, no zero errors.
///
/// Counters per measurement: ms_per_meas (wall), steps, rhs_evals (incl. finite-difference
/// Jacobians), jac_evals, rhs_ns (mean cost of one RHS call), rhs_share = rhs_evals x rhs_ns
/// / ms_per_meas. RHS cost method: the RHS is internal to static_unbalance_procedure.cc, so
/// replica_rhs copies its arithmetic; at startup it drives a CvodeIntegrator through one
/// position (theta = 45 deg, model solver settings) recording the (t, y) of every call, and
/// those realistic inputs are then replayed through a function pointer and timed. Not
/// counted: CVODE's C-callback shim (cvode_rhs, 2 x N_VGetArrayPointer), a few ns per call.
///
/// Accuracy (once at startup, printed to stderr; counters of BM_Measurement36): the 36-point
/// measurement with every acquisition noise and offset term at its default 0 and no
/// positioning error (ADC kept), at the model's tolerances and at tight_plan (fixed tolerances):
/// tol_torque_rel = |dMT_s| / load torque (must be < 1e-3), tol_phase_deg = |db|.
/// Run: poise_gimbal_bench --benchmark_min_time=1
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "core/units.h"
#include "models/disk_rotor.h"
#include "procedures/static_unbalance_procedure.h"
#include "sampling/random_stream.h"
#include "solvers/cvode_integrator.h"
#include "model_files/gimbal_model.h"

using namespace poise::model_files;  // the kinds' and model files' own namespaces

namespace {

namespace pr = poise::procedures;
using poise::units::kPi;
using poise::units::kRadPerDeg;
using Clock = std::chrono::steady_clock;

constexpr double kClump = 25.81e-3, kRadius = 0.051, kAngle = 45.5 * kRadPerDeg;
constexpr std::uint64_t kSeed = 2015;

std::filesystem::path source_dir() {  // $POISE_SOURCE_DIR, else bench/.. (__FILE__ is absolute)
  if (const char* env = std::getenv("POISE_SOURCE_DIR"); env != nullptr && *env != '\0') return env;
  return std::filesystem::path(__FILE__).parent_path().parent_path();
}

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// ---- REPLICA of the right-hand side of procedures/static_unbalance_procedure.cc, FOR TIMING
// ONLY (reference, PID + feed-forward clamped current, disk_accelerations, conditional
// integral, finiteness check). Keep in step with that file. `record` is null when timed.
struct RhsReplica {
  poise::models::DiskRotorParams disk;
  poise::models::GimbalGravity gravity;
  double kp = 0, kd = 0, ki = 0, j_ff = 0, kt_nominal = 1, kt_true = 1, i_max = 1;
  double t0 = 0, omega = 1, amplitude = 0, rate_amplitude = 0, centre = 0;
  long calls = 0;
  std::vector<std::array<double, 8>>* record = nullptr;  // (t, y) of every call
};

int replica_rhs(double t, const double* y, double* ydot, void* user) {
  auto* c = static_cast<RhsReplica*>(user);
  ++c->calls;
  if (c->record) c->record->push_back({t, y[0], y[1], y[2], y[3], y[4], y[5], y[6]});
  double phi_r = c->centre - c->amplitude, rate_r = 0.0, acc_r = 0.0;
  if (t >= c->t0) {
    const double w = c->omega * (t - c->t0);
    phi_r = c->centre - c->amplitude * std::cos(w);
    rate_r = c->rate_amplitude * std::sin(w);
    acc_r = c->rate_amplitude * c->omega * std::cos(w);
  }
  const double cmd = (c->kp * (phi_r - y[0]) + c->kd * (rate_r - y[1]) + c->ki * y[6] + c->j_ff * acc_r) /
                     c->kt_nominal;
  const double i = std::clamp(cmd, -c->i_max, c->i_max);
  const poise::models::DiskState s{y[0], y[1], y[2], y[3], y[4], y[5]};
  const auto acc = poise::models::disk_accelerations(c->disk, c->gravity, s, c->kt_true * i);
  ydot[0] = y[1], ydot[1] = acc[0], ydot[2] = y[3], ydot[3] = acc[1], ydot[4] = y[5], ydot[5] = acc[2];
  ydot[6] = i != cmd ? 0.0 : phi_r - y[0];
  for (int k = 0; k < 7; ++k) if (!std::isfinite(ydot[k])) return 1;
  return 0;
}

pr::TestPlan make_plan(const poise::model_files::GimbalModel& m, int positions, double rate_hz) {
  pr::TestPlan plan = m.plan;  // the model's servo, oscillation, acquisition and solver
  plan.positions.clear();
  for (int p = 0; p < positions; ++p) plan.positions.push_back(2.0 * kPi * p / positions);
  plan.acquisition.rate_hz = rate_hz;
  return plan;
}

pr::MeasurementResult measure(const pr::TestPlan& plan, const pr::GimbalTruth& truth,
                              std::uint64_t seed = kSeed) {
  pr::StaticUnbalanceWorkspace ws(plan.solver);
  poise::sampling::RandomStream rs(seed, poise::sampling::StreamId::kProcedure, 0);
  return pr::run_static_unbalance_procedure(plan, truth, rs, ws);
}

// The rig's rotor with a clump of `mass` at kRadius and `angle` (as studies/gimbal_study.cc
// adds it); nominal K_T.
pr::GimbalTruth clump_on_rotor(const poise::model_files::GimbalModel& model, double mass, double angle) {
  pr::GimbalTruth truth;
  truth.disk = model.rotor;
  truth.disk.mass = model.rotor.mass + mass;
  truth.disk.inertia = model.rotor.inertia + mass * kRadius * kRadius;
  truth.disk.eccentricity = mass * kRadius / truth.disk.mass;
  truth.disk.eccentricity_angle = angle;
  truth.kt_true = model.plan.servo.kt_nominal;
  return truth;
}

// The reference solution's settings: rtol 1e-10 and absolute tolerances of 1e-10 rad on the
// angles and 1e-13 m on the support deflections (their rates in the model's proportion), fixed
// whatever the model's own tolerances are, so that loosening those does not move the reference.
pr::TestPlan tight_plan(pr::TestPlan plan) {
  plan.solver.rtol = 1e-10;
  std::vector<double>& a = plan.solver.atol_per_state;  // phi, phi', y, y', z, z', servo integral
  const double angle = 1e-10 / a.at(0), length = 1e-13 / a.at(2);
  for (std::size_t k = 0; k < a.size(); ++k) a[k] *= (k >= 2 && k <= 5) ? length : angle;
  plan.solver.atol *= angle;
  return plan;
}

// The accuracy sweep: four rotors (clumps of 25.81, 10, 50 and 5 g at 51 mm, 45.5 + 70 k deg)
// by three noise seeds, each with its reference MT_s.
struct SweepCase {
  pr::GimbalTruth truth;
  std::uint64_t seed = 0;
  double reference = 0, reference_offset = 0;  ///< MT_s and MK at tight_plan (N m)
};

std::vector<SweepCase> accuracy_sweep(const poise::model_files::GimbalModel& model, const pr::TestPlan& plan) {
  std::vector<SweepCase> cases;
  const double masses[] = {kClump, 10e-3, 50e-3, 5e-3};
  for (int r = 0; r < 4; ++r) {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      SweepCase c{clump_on_rotor(model, masses[r], (45.5 + 70.0 * r) * kRadPerDeg), seed, 0.0, 0.0};
      pr::TestPlan t = tight_plan(plan);
      t.supports = pr::Supports::kDynamic;
      const auto fit = measure(t, c.truth, seed).fit;
      c.reference = fit.amplitude, c.reference_offset = fit.offset;
      cases.push_back(c);
    }
  }
  return cases;
}

// Mean cost (ns) of one RHS call, by the record-and-replay method described above.
double rhs_cost_ns(const pr::TestPlan& plan, const pr::GimbalTruth& truth, long* calls_per_position) {
  const pr::ServoConfig& sv = plan.servo;
  const pr::OscillationConfig& osc = plan.oscillation;
  RhsReplica c;  // the same set-up as run_static_unbalance_procedure
  const double wc = 2.0 * kPi * sv.bandwidth_hz;
  c.disk = truth.disk, c.gravity = poise::models::gravity_in_gimbal(plan.gravity, 45.0 * kRadPerDeg);
  c.kp = sv.inertia_estimate * wc * wc, c.kd = 2.0 * sv.damping * sv.inertia_estimate * wc;
  c.ki = c.kp * wc * sv.integral_ratio, c.j_ff = sv.inertia_estimate;
  c.kt_nominal = sv.kt_nominal, c.kt_true = truth.kt_true, c.i_max = sv.current_limit;
  c.omega = 2.0 * kPi / osc.period, c.rate_amplitude = osc.rate_amplitude;
  c.amplitude = osc.rate_amplitude / c.omega, c.centre = osc.centre, c.t0 = osc.settle_time;
  std::vector<std::array<double, 8>> rec;  // recorded inputs, then replayed
  c.record = &rec;
  poise::solvers::CvodeIntegrator integ(7, replica_rhs, &c, plan.solver);
  const auto defl = poise::models::static_deflection(c.disk, c.gravity);
  const double y0[7] = {osc.centre - c.amplitude, 0.0, defl[0], 0.0, defl[1], 0.0, 0.0};
  const double t2 = osc.settle_time + osc.lead_in + osc.periods * osc.period;
  integ.reset(0.0, y0);
  integ.advance(c.t0, c.t0, false);
  integ.advance(t2, t2, false);
  *calls_per_position = c.calls, c.record = nullptr;
  int (*volatile f)(double, const double*, double*, void*) = replica_rhs;  // no inlining
  double ydot[7];
  long n = 0;  // calls timed
  const auto start = Clock::now();
  do {
    for (const auto& r : rec) f(r[0], r.data() + 1, ydot, &c), benchmark::DoNotOptimize(ydot);
    n += static_cast<long>(rec.size());
  } while (seconds_since(start) < 0.3);
  return seconds_since(start) / static_cast<double>(n) * 1e9;
}

// Built once on first use, never inside a timed loop.
struct Setup {
  poise::model_files::GimbalModel model;
  pr::GimbalTruth truth;
  double load_torque = 0, rhs_ns = 0, torque_rel = 0, phase_deg = 0;
  double tight_amplitude = 0;  ///< MT_s of the model's acquisition at tight_plan (dynamic)
  std::vector<SweepCase> sweep;
  long replica_calls = 0;

  Setup()
      : model(poise::model_files::load_gimbal_model(
            (source_dir() / "models" / "gimbal_simulator_yang2015.toml").string())) {
    truth = clump_on_rotor(model, kClump, kAngle);
    load_torque = kClump * kRadius * model.plan.gravity;
    const pr::TestPlan plan = make_plan(model, 36, model.plan.acquisition.rate_hz);
    rhs_ns = rhs_cost_ns(plan, truth, &replica_calls);
    tight_amplitude = measure(tight_plan(plan), truth).fit.amplitude;
    sweep = accuracy_sweep(model, plan);
    // Accuracy: noise, offsets and positioning error off; model vs tightened tolerances.
    pr::TestPlan quiet = plan;
    quiet.acquisition = pr::AcquisitionConfig{};  // every noise and offset term 0 by default
    quiet.acquisition.rate_hz = plan.acquisition.rate_hz, quiet.positioning_error = 0.0;
    quiet.acquisition.adc_bits = plan.acquisition.adc_bits;
    quiet.acquisition.adc_full_scale = plan.acquisition.adc_full_scale;
    const auto t_acc = Clock::now();
    const pr::MeasurementResult a = measure(quiet, truth), b = measure(tight_plan(quiet), truth);
    const double s_tight = seconds_since(t_acc);
    torque_rel = std::abs(a.fit.amplitude - b.fit.amplitude) / load_torque;
    phase_deg = std::abs(std::remainder(a.fit.phase - b.fit.phase, 2.0 * kPi)) / kRadPerDeg;
    std::fprintf(stderr,
                 "accuracy (36 positions, noise off): MT_s %.6f mN*m at the model's tolerances (%ld steps),"
                 " %.6f at tight_plan (%ld steps; both runs %.0f ms)\n  |dMT_s| / load = %.2e"
                 " (limit 1e-3: %s), |d phase| = %.2e deg; load %.4f mN*m\n  RHS replica: %.1f ns/call;"
                 " %ld calls for one position (the procedure: %.0f per position)\n",
                 a.fit.amplitude * 1e3, a.solver.steps, b.fit.amplitude * 1e3, b.solver.steps, s_tight * 1e3,
                 torque_rel, torque_rel < 1e-3 ? "OK" : "FAILED", phase_deg, load_torque * 1e3, rhs_ns,
                 replica_calls, static_cast<double>(a.solver.rhs_evals) / 36.0);
  }
};

const Setup& setup() {
  static const Setup s;
  return s;
}

// One complete measurement per iteration, the workspace kept as a study thread keeps it.
void measurement(benchmark::State& state, int positions) {
  const Setup* sp = nullptr;
  pr::MeasurementResult m;
  double seconds = 0;
  try {
    sp = &setup();
    const pr::TestPlan plan = make_plan(sp->model, positions, static_cast<double>(state.range(0)));
    pr::StaticUnbalanceWorkspace ws(plan.solver);
    for (auto _ : state) {
      poise::sampling::RandomStream rs(kSeed, poise::sampling::StreamId::kProcedure, 0);
      const auto t0 = Clock::now();
      m = pr::run_static_unbalance_procedure(plan, sp->truth, rs, ws);
      seconds += seconds_since(t0);
      benchmark::DoNotOptimize(m.fit.amplitude);
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  const double per = seconds / static_cast<double>(state.iterations());  // s per measurement
  const auto evals = static_cast<double>(m.solver.rhs_evals);
  state.counters.insert({{"ms_per_meas", per * 1e3}, {"steps", static_cast<double>(m.solver.steps)},
                         {"rhs_evals", evals}, {"jac_evals", static_cast<double>(m.solver.jac_evals)},
                         {"rhs_ns", sp->rhs_ns}, {"rhs_share", evals * sp->rhs_ns * 1e-9 / per}});
  if (positions == 36)
    state.counters.insert({{"tol_torque_rel", sp->torque_rel}, {"tol_phase_deg", sp->phase_deg}});
}

void BM_Measurement36(benchmark::State& state) { measurement(state, 36); }
void BM_Measurement18(benchmark::State& state) { measurement(state, 18); }
BENCHMARK(BM_Measurement36)->ArgName("rate")->Arg(500)->Arg(50)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Measurement18)->ArgName("rate")->Arg(500)->Arg(50)->Unit(benchmark::kMillisecond);

// The 36-point measurement by support formulation (0 dynamic, 1 quasi-static) and solver
// tolerance (rtol and atol times `loose`: 1 = the model's, 10 = ten times looser), the model's
// acquisition (noise drawn in distribution). Counter tol_torque_rel: |MT_s - MT_s(tight)| /
// load, MT_s(tight) from the dynamic model at tight_plan, the same seed (the noise draws are
// the same, so the difference is the solver's alone); worst_torque_rel and worst_offset_rel
// the largest over the accuracy sweep. Target (issue 19): within 1e-4, at >= 50x the CPU time
// of bench/baselines/gimbal_scipy.py.
void BM_Measurement36By(benchmark::State& state) {
  const Setup& sp = setup();
  pr::TestPlan plan = make_plan(sp.model, 36, sp.model.plan.acquisition.rate_hz);
  plan.supports = state.range(0) == 1 ? pr::Supports::kQuasiStatic : pr::Supports::kDynamic;
  const auto loose = static_cast<double>(state.range(1));
  plan.solver.rtol *= loose, plan.solver.atol *= loose;
  for (double& a : plan.solver.atol_per_state) a *= loose;
  if (state.range(2) > 0) plan.solver.max_order = static_cast<int>(state.range(2));
  pr::StaticUnbalanceWorkspace ws(plan.solver);
  pr::MeasurementResult m;
  for (auto _ : state) {
    poise::sampling::RandomStream rs(kSeed, poise::sampling::StreamId::kProcedure, 0);
    m = pr::run_static_unbalance_procedure(plan, sp.truth, rs, ws);
    benchmark::DoNotOptimize(m.fit.amplitude);
  }
  double worst = 0, worst_offset = 0;  // over the accuracy sweep, outside the timing
  for (const SweepCase& c : sp.sweep) {
    const auto fit = measure(plan, c.truth, c.seed).fit;
    worst = std::max(worst, std::abs(fit.amplitude - c.reference));
    worst_offset = std::max(worst_offset, std::abs(fit.offset - c.reference_offset));
  }
  state.counters.insert({{"steps", static_cast<double>(m.solver.steps)},
                         {"rhs_evals", static_cast<double>(m.solver.rhs_evals)},
                         {"tol_torque_rel", std::abs(m.fit.amplitude - sp.tight_amplitude) / sp.load_torque},
                         {"worst_torque_rel", worst / sp.load_torque},
                         {"worst_offset_rel", worst_offset / sp.load_torque}});
}
BENCHMARK(BM_Measurement36By)->ArgNames({"quasi_static", "loose", "max_order"})
    ->Args({0, 1, 0})->Args({1, 1, 0})->Args({0, 2, 0})->Args({0, 3, 0})->Args({1, 3, 0})->Args({0, 10, 0})
    ->Args({1, 10, 0})->Args({1, 5, 0})->Args({1, 1, 5})->Args({1, 10, 5})->Unit(benchmark::kMillisecond);

}  // namespace
