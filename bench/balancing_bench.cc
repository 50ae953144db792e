/// Benchmarks of one complete simulated balancing run of the spring-plate hard-bearing
/// balancing machine (Wang & Wang 2014; Google Benchmark 1.7.1).
///
///   BM_BalancingRun  procedures::run_balancing_measurement on the rotor below: CVODE (BDF,
///     the model's solver settings) from rest through the start transient to steady state
///     (settling of settle_time_constants decay time constants, whole revolutions), the
///     encoder-triggered sampling of both sensors with the model's white noise, synchronous
///     demodulation over the model's whole revolutions; then both estimates of the unbalance:
///     the corrected closed form (Eq. 13) and influence coefficients, the calibration
///     (bare rotor, test mass on plane 1, on plane 2) precomputed once outside the timing loop.
///     Each iteration draws its noise from a new RandomStream index, as a study's samples do.
///     Target (issue): <= 5 ms per run per core.
///   BM_BalancingRun_rtol/rtol_exp:E  the same run without noise, solver rtol = atol = 1e-E
///     (atol is relative to the response: the states are scaled by the exact steady state),
///     E = 3, 4, 5, 6 (the model's), 8, 10: the accuracy/speed trade-off. amp_rel_err = max over the
///     two sensors of |A - A_exact| / |A_exact|, A_exact = sensor_forces(steady_state_response).
///
/// Machine: models/balancing_machine_wang2014.toml (load_balancing_model; found via
/// $POISE_SOURCE_DIR, else the POISE_SOURCE_DIR compile definition), nominal as built, with
/// the model's standard rotor R, run settings and sensors. Correction planes: testing
/// surfaces 2 and 6; reference height 0 (Eq. 2 as printed).
///   Rotor measured: 20 g at 50 mm on surface 2 at 30 deg, 15 g at 50 mm on surface 6 at
///     -100 deg (plane unbalances 1.0 and 0.75 kg*mm).
///   Calibration rotor: the model's residual unbalances (rotor_residual_1, _2) on surfaces 2
///     and 6 at 70 and 200 deg; test masses 20 g at 50 mm, 0 deg, on surface 2, then 6.
///     Noise-free calibration runs (the influence matrix is then exact; the check below needs it).
///
/// Checks (once at startup, printed to stderr; the program aborts if one fails):
///   * the noise-free demodulated amplitudes of the rotor's run equal the exact steady state
///     sensor_forces(machine, steady_state_response(...)) to relative 1e-5, each sensor;
///   * the noise-free influence estimate recovers the rotor's plane unbalances to 1e-4
///     relative, each plane.
///
/// Counters per run: steps, rhs_evals (incl. finite-difference Jacobians), jac_evals,
/// sim_s (simulated seconds: settling + acquisition), runs_per_s (iterations per CPU second),
/// and for BM_BalancingRun infl_rms_err / cf_rms_err: the largest relative plane-unbalance
/// error of the influence and closed-form estimates, RMS over all the (noisy) timed runs
/// (computed inside the loop: a few complex divisions, negligible against the run).
/// Run: poise_balancing_bench --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "core/units.h"
#include "models/spring_plate_machine.h"
#include "procedures/balancing_measurement.h"
#include "sampling/random_stream.h"
#include "kinds/balancing_machine/balancing_model.h"

using namespace poise::kinds::balancing_machine;  // the kinds' and model files' own namespaces

#ifndef POISE_SOURCE_DIR
#error "POISE_SOURCE_DIR must be defined (bench/CMakeLists.txt)"
#endif

namespace {

namespace pr = poise::procedures;
namespace md = poise::models;
using poise::units::kRadPerDeg;
using cd = std::complex<double>;

constexpr std::uint64_t kSeed = 2014;
constexpr int kPlane1 = 2, kPlane2 = 6;  // testing surfaces used as correction planes

std::filesystem::path source_dir() {
  if (const char* env = std::getenv("POISE_SOURCE_DIR"); env != nullptr && *env != '\0') return env;
  return POISE_SOURCE_DIR;
}

[[noreturn]] void fail(const char* what, double value, double limit) {
  std::fprintf(stderr, "poise_balancing_bench: CHECK FAILED: %s = %.3e (limit %.1e)\n", what, value, limit);
  std::abort();
}

cd unbalance_of(const md::PlaneMass& m) { return m.mass * m.radius * std::polar(1.0, m.angle); }

// Largest relative error over the two components.
double max_rel(const Eigen::Vector2cd& got, const Eigen::Vector2cd& exact) {
  return std::max(std::abs(got(0) - exact(0)) / std::abs(exact(0)), std::abs(got(1) - exact(1)) / std::abs(exact(1)));
}

// Built once on first use, never inside a timed loop.
struct Setup {
  poise::kinds::balancing_machine::BalancingModel model;
  md::SpringPlateMachineParams machine;
  pr::CorrectionPlanes planes;
  std::vector<md::PlaneMass> rotor;
  Eigen::Vector2cd true_planes;  // the rotor's plane unbalances (kg m)
  Eigen::Vector2cd exact;        // exact steady-state sensor amplitudes of the rotor (N)
  pr::InfluenceCalibration calibration;
  pr::SensorConfig quiet;        // the model's sensors without noise

  Setup()
      : model(poise::kinds::balancing_machine::load_balancing_model(
            (source_dir() / "models" / "balancing_machine_wang2014.toml").string())) {
    machine = poise::kinds::balancing_machine::machine_params(model, poise::kinds::balancing_machine::nominal_as_built(model), model.rotor);
    const double z1 = model.rotor.surface_height(kPlane1), z2 = model.rotor.surface_height(kPlane2);
    planes = {z1, z2};
    rotor = {{20e-3, 0.050, 30.0 * kRadPerDeg, z1}, {15e-3, 0.050, -100.0 * kRadPerDeg, z2}};
    true_planes = {unbalance_of(rotor[0]), unbalance_of(rotor[1])};
    quiet = model.sensors;
    quiet.noise_rms = 0.0;
    const double omega = md::rpm_to_rad_per_s(model.run.speed_rpm);
    exact = md::sensor_forces(
        machine, md::steady_state_response(machine, md::to_machine_unbalance(md::resultant_unbalance(rotor, 0.0)),
                                           omega));

    pr::BalancingWorkspace ws(model.run.solver);
    poise::sampling::RandomStream unused(kSeed, poise::sampling::StreamId::kProcedure, 0);
    const auto run = [&](std::span<const md::PlaneMass> masses) {
      return pr::run_balancing_measurement(machine, masses, 0.0, model.run, quiet, unused, ws);
    };
    // Calibration (noise-free): the standard rotor's residuals, then a test mass per plane.
    const double r = 0.050;
    std::vector<md::PlaneMass> cal = {
        {model.rotor_residual_1.spec.tolerance / r, r, 70.0 * kRadPerDeg, z1},
        {model.rotor_residual_2.spec.tolerance / r, r, 200.0 * kRadPerDeg, z2}};
    const md::PlaneMass test_1{20e-3, r, 0.0, z1}, test_2{20e-3, r, 0.0, z2};
    const Eigen::Vector2cd a0 = run(cal).amplitudes;
    cal.push_back(test_1);
    const Eigen::Vector2cd a1 = run(cal).amplitudes;
    cal.back() = test_2;
    const Eigen::Vector2cd a2 = run(cal).amplitudes;
    calibration = pr::calibrate_influence(a0, a1, unbalance_of(test_1), a2, unbalance_of(test_2));

    // Checks on the rotor's noise-free run.
    const pr::BalancingMeasurement m = run(rotor);
    const double amp_err = max_rel(m.amplitudes, exact);
    const Eigen::Vector2cd infl = pr::influence_estimate(calibration, m.amplitudes);
    const double infl_err = max_rel(infl, true_planes);
    const pr::ClosedFormEstimate cf = pr::closed_form_estimate(machine, m.amplitudes, m.omega, 0.0, planes);
    const double cf_err = max_rel(cf.planes, true_planes);
    const md::NaturalFrequencies nf = md::natural_frequencies(machine);
    std::fprintf(stderr,
                 "balancing run (noise off, model tolerances rtol %.0e atol %.0e, max order %d): omega %.4f rad/s,"
                 " omega_1 %.1f, omega_2 %.1f rad/s\n  settle %d rev (%.3f s, tau %.4f s) + %d rev at %d samples/rev;"
                 " %ld steps, %ld rhs evals, %ld jac evals\n"
                 "  |F1| %.4e N, |F2| %.4e N; amplitude rel err %.2e (limit 1e-5: %s); last-rev change %.1e %.1e\n"
                 "  influence estimate rel err %.2e (limit 1e-4: %s); closed form rel err %.2e (hard-bearing"
                 " approximation, not checked)\n",
                 model.run.solver.rtol, model.run.solver.atol, model.run.solver.max_order, m.omega, nf.omega_1,
                 nf.omega_2, m.settle_revolutions, m.settle_time, m.decay_time_constant, model.run.revolutions,
                 m.samples_per_revolution, m.solver.steps, m.solver.rhs_evals, m.solver.jac_evals,
                 std::abs(exact(0)), std::abs(exact(1)), amp_err, amp_err < 1e-5 ? "OK" : "FAILED",
                 m.last_revolution_change(0), m.last_revolution_change(1), infl_err,
                 infl_err < 1e-4 ? "OK" : "FAILED", cf_err);
    if (!(amp_err < 1e-5)) fail("noise-free amplitude rel err vs exact steady state", amp_err, 1e-5);
    if (!(infl_err < 1e-4)) fail("noise-free influence estimate rel err vs the rotor's plane unbalances", infl_err, 1e-4);
  }
};

const Setup& setup() {
  static const Setup s;
  return s;
}

struct RunResult {
  pr::BalancingMeasurement measurement;
  Eigen::Vector2cd influence;
  Eigen::Vector2cd closed_form;
};

// One complete run: measurement, then both estimates.
RunResult balancing_run(const Setup& s, const pr::BalancingRunConfig& run, const pr::SensorConfig& sensors,
                        poise::sampling::RandomStream& noise, pr::BalancingWorkspace& ws) {
  RunResult r;
  r.measurement = pr::run_balancing_measurement(s.machine, s.rotor, 0.0, run, sensors, noise, ws);
  r.influence = pr::influence_estimate(s.calibration, r.measurement.amplitudes);
  r.closed_form =
      pr::closed_form_estimate(s.machine, r.measurement.amplitudes, r.measurement.omega, 0.0, s.planes).planes;
  return r;
}

void add_counters(benchmark::State& state, const pr::BalancingMeasurement& m, const pr::BalancingRunConfig& run) {
  const double period = 2.0 * poise::units::kPi / m.omega;
  state.counters.insert({{"steps", static_cast<double>(m.solver.steps)},
                         {"rhs_evals", static_cast<double>(m.solver.rhs_evals)},
                         {"jac_evals", static_cast<double>(m.solver.jac_evals)},
                         {"sim_s", m.settle_time + run.revolutions * period},
                         {"runs_per_s", benchmark::Counter(static_cast<double>(state.iterations()),
                                                           benchmark::Counter::kIsRate)}});
}

void BM_BalancingRun(benchmark::State& state) {
  RunResult r;
  const Setup* sp = nullptr;
  double infl_sq = 0.0, cf_sq = 0.0;
  try {
    sp = &setup();
    pr::BalancingWorkspace ws(sp->model.run.solver);
    std::uint64_t index = 0;
    for (auto _ : state) {
      poise::sampling::RandomStream noise(kSeed, poise::sampling::StreamId::kProcedure, ++index);
      r = balancing_run(*sp, sp->model.run, sp->model.sensors, noise, ws);
      const double ei = max_rel(r.influence, sp->true_planes), ec = max_rel(r.closed_form, sp->true_planes);
      infl_sq += ei * ei, cf_sq += ec * ec;
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  add_counters(state, r.measurement, sp->model.run);
  const auto n = static_cast<double>(state.iterations());
  state.counters.insert({{"infl_rms_err", std::sqrt(infl_sq / n)}, {"cf_rms_err", std::sqrt(cf_sq / n)}});
}

void BM_BalancingRun_rtol(benchmark::State& state) {
  RunResult r;
  const Setup* sp = nullptr;
  pr::BalancingRunConfig run;
  try {
    sp = &setup();
    run = sp->model.run;
    run.solver.rtol = run.solver.atol = std::pow(10.0, -static_cast<double>(state.range(0)));
    pr::BalancingWorkspace ws(run.solver);
    poise::sampling::RandomStream unused(kSeed, poise::sampling::StreamId::kProcedure, 0);
    for (auto _ : state) {
      r = balancing_run(*sp, run, sp->quiet, unused, ws);
      benchmark::DoNotOptimize(r.influence.data());
      benchmark::DoNotOptimize(r.closed_form.data());
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  add_counters(state, r.measurement, run);
  state.counters.insert({{"amp_rel_err", max_rel(r.measurement.amplitudes, sp->exact)}});
}

BENCHMARK(BM_BalancingRun)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BalancingRun_rtol)->ArgName("rtol_exp")->Arg(3)->Arg(4)->Arg(5)->Arg(6)->Arg(8)->Arg(10)->Unit(benchmark::kMillisecond);

}  // namespace
