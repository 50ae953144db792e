// Measurement procedure of the spring-plate hard-bearing balancing machine (Wang & Wang 2014):
// synchronous demodulation, CVODE run against the exact steady state, the corrected closed
// form (Eq. 13) against its hard-bearing error, influence coefficients (exact, gain-free),
// determinism with noise.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <vector>

#include "core/error.h"
#include "models/spring_plate_machine.h"
#include "procedures/balancing_measurement.h"
#include "sampling/random_stream.h"

namespace poise::procedures {
namespace {

constexpr double kPi = 3.14159265358979323846;
using cd = std::complex<double>;
using models::PlaneMass;
using models::SpringPlateMachineParams;

// The machine of tests/models/spring_plate_machine_test.cc (plausible Wang 2014 values).
SpringPlateMachineParams wang2014(double zeta) {
  const models::SpringPlate horizontal{0.100, 0.150, 0.004, 206e9};
  const models::SpringPlate torsional{0.080, 0.100, 0.005, 206e9};
  const double m_r = 47.6, h_r = 0.510, r_r = 0.050, z_r = 0.070 + h_r / 2;
  const double j_r = m_r * (3 * r_r * r_r + h_r * h_r) / 12;
  const double m_s = 40.0, z_s = 0.0, j_s = 0.5;
  SpringPlateMachineParams p;
  p.rotating_mass = m_r + m_s;
  p.mass_centre_height = (m_r * z_r + m_s * z_s) / p.rotating_mass;
  const double H = p.mass_centre_height;
  p.inertia = j_r + m_r * (z_r - H) * (z_r - H) + j_s + m_s * (z_s - H) * (z_s - H);
  p.total_mass = p.rotating_mass + 30.0;
  p.lever = 0.250;
  p.horizontal_plate_stiffness = models::guided_plate_stiffness(horizontal);
  p.torsional_plate_stiffness = models::guided_plate_stiffness(torsional);
  const Eigen::Matrix2d m = models::mass_matrix(p), k = models::stiffness_matrix(p);
  p.damping_x = 2 * zeta * std::sqrt(k(0, 0) * m(0, 0));
  p.damping_theta = 2 * zeta * std::sqrt(k(1, 1) * m(1, 1));
  return p;
}

double rel(cd a, cd b) { return std::abs(a - b) / std::abs(b); }
cd unb(const PlaneMass& m) { return m.mass * m.radius * std::polar(1.0, m.angle); }

// Correction planes: testing surfaces 1 and 8 of Wang 2014 (150 and 500 mm above the shaft).
constexpr double kZ1 = 0.150, kZ2 = 0.500;
// Unknown rotor: 12 g at 40 deg on plane 1, 30 g at -120 deg on plane 2, radius 50 mm.
const std::vector<PlaneMass> kRotor{{0.012, 0.050, 40 * kPi / 180, kZ1}, {0.030, 0.050, -120 * kPi / 180, kZ2}};
// Calibration rotor (its own unbalance unknown to the procedure) and 20 g test masses.
const std::vector<PlaneMass> kCalRotor{{0.008, 0.050, 100 * kPi / 180, kZ1}, {0.005, 0.050, 10 * kPi / 180, kZ2}};
const PlaneMass kTest1{0.020, 0.050, 0.0, kZ1}, kTest2{0.020, 0.050, 0.0, kZ2};

TEST(BalancingMeasurement, DemodulationIsExactOverWholeRevolutions) {
  const cd a = std::polar(0.37, -2.1);
  const int spr = 17, revs = 3;
  const double phi0 = 0.3 + 10 * kPi;  // encoder zero anywhere
  std::vector<double> s, phi;
  for (int k = 0; k < spr * revs; ++k) {
    const double p = phi0 + 2 * kPi * k / spr;
    phi.push_back(p);
    // DC offset and harmonics 2 and 5 must cancel.
    s.push_back(0.7 + std::real(a * std::polar(1.0, p)) + 0.4 * std::cos(2 * p + 1) + 0.2 * std::cos(5 * p - 0.4));
  }
  const cd got = demodulate(s, phi);
  std::printf("demodulation error %.3e (|A| = 0.37)\n", std::abs(got - a));
  EXPECT_LT(std::abs(got - a), 1e-12);
  // Over 2.5 revolutions the DC offset leaks into the estimate: whole revolutions matter.
  const std::size_t half = static_cast<std::size_t>(spr * 5 / 2);
  const cd partial = demodulate(std::span(s).first(half), std::span(phi).first(half));
  EXPECT_GT(std::abs(partial - a), 1e-2);
  EXPECT_THROW(demodulate(std::span(s).first(3), std::span(phi).first(2)), Error);
}

TEST(BalancingMeasurement, SimulatedAmplitudesMatchExactSteadyState) {
  const SpringPlateMachineParams p = wang2014(0.02);
  const models::SpringPlateUnbalance u{1e-3, 0.4, 0.30, 5e-3, -1.1};  // U, a3, h, V, a4
  BalancingRunConfig run;
  SensorConfig sensors;
  sampling::RandomStream rs(1, sampling::StreamId::kProcedure, 0);
  BalancingWorkspace ws(run.solver);
  const BalancingMeasurement m = run_balancing_measurement(p, u, run, sensors, rs, ws);
  const Eigen::Vector2cd exact = models::sensor_forces(p, models::steady_state_response(p, u, m.omega));
  const double e1 = rel(m.amplitudes(0), exact(0)), e2 = rel(m.amplitudes(1), exact(1));
  std::printf("omega %.4f rad/s, omega_1 %.2f rad/s, tau %.4f s, settle %d rev (%.3f s), %d samples/rev, "
              "%ld steps\n", m.omega, models::natural_frequencies(p).omega_1, m.decay_time_constant,
              m.settle_revolutions, m.settle_time, m.samples_per_revolution, m.solver.steps);
  std::printf("F1 %.6e N rel err %.3e; F2 %.6e N rel err %.3e; last-rev change %.2e %.2e\n",
              std::abs(exact(0)), e1, std::abs(exact(1)), e2, m.last_revolution_change(0),
              m.last_revolution_change(1));
  EXPECT_LT(e1, 1e-4);
  EXPECT_LT(e2, 1e-4);
  // 20 time constants of settling: the transient is below 1e-8 of the response.
  EXPECT_GE(m.settle_time, 20.0 * m.decay_time_constant);
  EXPECT_LT(m.last_revolution_change.maxCoeff(), 1e-6);

  // Without settling (window = the first 2 revolutions from rest) the amplitude is off and
  // the settling check sees it. The transient rings at omega_1, omega_2 (not synchronous), so
  // the demodulation rejects most of it; what leaks is its decay within the window.
  BalancingRunConfig early = run;
  early.settle_time_constants = 0.0;
  early.min_settle_revolutions = 0;
  early.revolutions = 2;
  const BalancingMeasurement me = run_balancing_measurement(p, u, early, sensors, rs, ws);
  std::printf("without settling: rel err %.3e %.3e, last-rev change %.2e %.2e\n", rel(me.amplitudes(0), exact(0)),
              rel(me.amplitudes(1), exact(1)), me.last_revolution_change(0), me.last_revolution_change(1));
  EXPECT_GT(rel(me.amplitudes(0), exact(0)), 1e-4);
  EXPECT_GT(me.last_revolution_change.maxCoeff(), 1e-4);
}

TEST(BalancingMeasurement, UndampedMachineNeverSettles) {
  EXPECT_THROW(slowest_decay_rate(wang2014(0.0)), Error);
}

TEST(BalancingMeasurement, ClosedFormWithinHardBearingError) {
  const SpringPlateMachineParams p = wang2014(0.02);
  const double h = 0.0;  // Eq. 2 as printed: couple about the shaft axis
  BalancingRunConfig run;
  sampling::RandomStream rs(1, sampling::StreamId::kProcedure, 0);
  BalancingWorkspace ws(run.solver);
  const BalancingMeasurement m = run_balancing_measurement(p, kRotor, h, run, {}, rs, ws);
  const models::ResultantUnbalance truth = models::resultant_unbalance(kRotor, h);
  const ClosedFormEstimate est = closed_form_estimate(p, m.amplitudes, m.omega, h, {kZ1, kZ2});
  // The closed form applied to the model's exact steady state: its own (hard-bearing) error.
  const models::SpringPlateUnbalance u = models::to_machine_unbalance(truth);
  const ClosedFormEstimate model_cf = closed_form_estimate(
      p, models::sensor_forces(p, models::steady_state_response(p, u, m.omega)), m.omega, h, {kZ1, kZ2});
  const double dev_u = rel(model_cf.static_unbalance, truth.static_unbalance);
  const double dev_v = rel(model_cf.couple_unbalance, truth.couple_unbalance);
  const double err_u = rel(est.static_unbalance, truth.static_unbalance);
  const double err_v = rel(est.couple_unbalance, truth.couple_unbalance);
  const models::HardBearingCheck hb = models::check_hard_bearing(p, m.omega);
  std::printf("hard-bearing: omega_1/omega %.1f, deviation %.3e; closed form on exact steady state: U %.3e "
              "V %.3e; on the simulated run: U %.3e V %.3e\n", hb.ratio, hb.deviation, dev_u, dev_v, err_u, err_v);
  std::printf("U est %.6e kg m at %.4f rad (true %.6e at %.4f); V est %.6e kg m^2 at %.4f (true %.6e at %.4f)\n",
              std::abs(est.static_unbalance), std::arg(est.static_unbalance), std::abs(truth.static_unbalance),
              std::arg(truth.static_unbalance), std::abs(est.couple_unbalance), std::arg(est.couple_unbalance),
              std::abs(truth.couple_unbalance), std::arg(truth.couple_unbalance));
  // The run reproduces the model's closed-form result (simulation error < 1e-4)...
  EXPECT_LT(rel(est.static_unbalance, model_cf.static_unbalance), 1e-4);
  EXPECT_LT(rel(est.couple_unbalance, model_cf.couple_unbalance), 1e-4);
  // ...so its error is the hard-bearing approximation's, which at 80 r/min is small but not 0.
  EXPECT_LT(err_u, dev_u + 1e-4);
  EXPECT_LT(err_v, dev_v + 1e-4);
  EXPECT_LT(dev_u, 3.0 * hb.deviation);
  EXPECT_LT(dev_v, 3.0 * hb.deviation);
  EXPECT_GT(dev_u + dev_v, 1e-6);  // an approximation, not exact
  for (int i = 0; i < 2; ++i) {
    const double e = rel(est.planes(i), unb(kRotor[static_cast<std::size_t>(i)]));
    std::printf("closed form plane %d: %.6e kg m at %.2f deg, rel err %.3e\n", i + 1, std::abs(est.planes(i)),
                std::arg(est.planes(i)) * 180 / kPi, e);
    EXPECT_LT(e, 3.0 * hb.deviation + 1e-4);
  }
}

// Influence coefficients: exact for the linear machine; with gain errors unchanged, while the
// closed form is biased by exactly the gain error of sensor 1 in U.
TEST(BalancingMeasurement, InfluenceCoefficientsExactAndGainFree) {
  const SpringPlateMachineParams p = wang2014(0.02);
  const double h = 0.0;
  BalancingRunConfig run;
  BalancingWorkspace ws(run.solver);
  sampling::RandomStream rs(1, sampling::StreamId::kProcedure, 0);
  const UnbalanceEstimates ideal = estimate_unbalance(p, kCalRotor, kTest1, kTest2, kRotor, h, run, {}, rs, ws);
  SensorConfig gains;
  gains.gain_error_1 = 0.03;
  gains.gain_error_2 = -0.02;
  const UnbalanceEstimates biased = estimate_unbalance(p, kCalRotor, kTest1, kTest2, kRotor, h, run, gains, rs, ws);
  for (int i = 0; i < 2; ++i) {
    const auto si = static_cast<std::size_t>(i);
    const cd truth = unb(kRotor[si]);
    const double e_ideal = rel(ideal.influence(i), truth), e_gain = rel(biased.influence(i), truth);
    const double e_bare = rel(ideal.calibration.bare_unbalance(i), unb(kCalRotor[si]));
    const double e_cf_ideal = rel(ideal.closed_form.planes(i), truth);
    const double e_cf_gain = rel(biased.closed_form.planes(i), truth);
    std::printf("plane %d: IC rel err %.3e (gain errors %.3e), calibration rotor %.3e; closed form %.3e "
                "(gain errors %.3e)\n", i + 1, e_ideal, e_gain, e_bare, e_cf_ideal, e_cf_gain);
    EXPECT_LT(e_ideal, 1e-6);
    EXPECT_LT(e_gain, 1e-6);
    EXPECT_LT(e_bare, 1e-6);
    EXPECT_GT(e_cf_gain, 0.01);  // gain errors of a few % pass straight into the closed form
  }
  // The closed form's U scales with sensor 1's gain; V picks up both gains.
  const double ratio_u = std::abs(biased.closed_form.static_unbalance / ideal.closed_form.static_unbalance);
  std::printf("closed-form U ratio with/without gain error %.8f (1 + g1 = 1.03)\n", ratio_u);
  EXPECT_NEAR(ratio_u, 1.03, 1e-6);
  // The influence matrix absorbs the gains: its rows scale by (1 + g).
  EXPECT_LT((biased.calibration.coefficients.row(0) / 1.03 - ideal.calibration.coefficients.row(0)).norm() /
                ideal.calibration.coefficients.row(0).norm(), 1e-6);
  EXPECT_LT((biased.calibration.coefficients.row(1) / 0.98 - ideal.calibration.coefficients.row(1)).norm() /
                ideal.calibration.coefficients.row(1).norm(), 1e-6);
}

TEST(BalancingMeasurement, NoiseIsDeterministicForASeed) {
  const SpringPlateMachineParams p = wang2014(0.02);
  BalancingRunConfig run;
  SensorConfig sensors;
  sensors.noise_rms = 1e-3;  // N
  sensors.gain_error_1 = 0.01;
  BalancingWorkspace ws(run.solver), ws2(run.solver);
  sampling::RandomStream a(42, sampling::StreamId::kProcedure, 7), b(42, sampling::StreamId::kProcedure, 7),
      c(43, sampling::StreamId::kProcedure, 7);
  const UnbalanceEstimates ea = estimate_unbalance(p, kCalRotor, kTest1, kTest2, kRotor, 0.0, run, sensors, a, ws);
  const UnbalanceEstimates eb = estimate_unbalance(p, kCalRotor, kTest1, kTest2, kRotor, 0.0, run, sensors, b, ws2);
  const UnbalanceEstimates ec = estimate_unbalance(p, kCalRotor, kTest1, kTest2, kRotor, 0.0, run, sensors, c, ws);
  EXPECT_EQ(ea.measurement.amplitudes(0), eb.measurement.amplitudes(0));
  EXPECT_EQ(ea.measurement.amplitudes(1), eb.measurement.amplitudes(1));
  EXPECT_EQ(ea.influence(0), eb.influence(0));
  EXPECT_EQ(ea.influence(1), eb.influence(1));
  EXPECT_NE(ea.measurement.amplitudes(0), ec.measurement.amplitudes(0));
  // Noise on a complex amplitude: a and b each have rms sigma sqrt(2 / K) (K samples), so
  // |A - A0| has rms 2 sigma / sqrt(K).
  const double k = run.revolutions * ea.measurement.samples_per_revolution;
  const double sigma_a = 2.0 * sensors.noise_rms / std::sqrt(k);
  const SensorConfig clean{0.01, 0.0, 0.0, sensors.sample_rate_hz};
  sampling::RandomStream unused(0, sampling::StreamId::kProcedure, 0);
  const BalancingMeasurement m0 = run_balancing_measurement(p, kRotor, 0.0, run, clean, unused, ws);
  for (int i = 0; i < 2; ++i) {
    const double d = std::abs(ea.measurement.amplitudes(i) - m0.amplitudes(i));
    std::printf("sensor %d: noise on amplitude %.3e N (expected scale %.3e N, |A| %.3e N)\n", i + 1, d, sigma_a,
                std::abs(m0.amplitudes(i)));
    EXPECT_LT(d, 5.0 * sigma_a);
    EXPECT_GT(d, 0.0);
  }
  for (int i = 0; i < 2; ++i) {
    std::printf("plane %d with noise: IC rel err %.3e\n", i + 1, rel(ea.influence(i), unb(kRotor[static_cast<std::size_t>(i)])));
    EXPECT_LT(rel(ea.influence(i), unb(kRotor[static_cast<std::size_t>(i)])), 0.05);
  }
}

// The fast model (steady-state response) against the full one (CVODE from rest): the same
// noise draws in the same order, so the estimates differ only by the start transient left
// after settling and the solver's error; with noise off the settling check reads zero.
TEST(BalancingMeasurement, SteadyStateResponseMatchesTheIntegratedRun) {
  const SpringPlateMachineParams p = wang2014(0.02);
  BalancingRunConfig full;
  BalancingRunConfig fast = full;
  fast.response = BalancingResponse::kSteadyState;
  SensorConfig sensors;
  sensors.noise_rms = 1e-3;  // N
  sensors.gain_error_1 = 0.01;
  sensors.gain_error_2 = -0.02;
  sensors.sensor_1_offset = 0.003;
  BalancingWorkspace ws(full.solver);
  sampling::RandomStream a(42, sampling::StreamId::kProcedure, 7), b(42, sampling::StreamId::kProcedure, 7);
  const UnbalanceEstimates ef = estimate_unbalance(p, kCalRotor, kTest1, kTest2, kRotor, 0.0, full, sensors, a, ws);
  const UnbalanceEstimates es = estimate_unbalance(p, kCalRotor, kTest1, kTest2, kRotor, 0.0, fast, sensors, b, ws);
  EXPECT_EQ(a.uniform(), b.uniform());  // both streams advanced alike
  for (int i = 0; i < 2; ++i) {
    const double da = rel(es.measurement.amplitudes(i), ef.measurement.amplitudes(i));
    const double di = rel(es.influence(i), ef.influence(i));
    const double dc = rel(es.closed_form.planes(i), ef.closed_form.planes(i));
    std::printf("sensor/plane %d: amplitude %.2e, influence %.2e, closed form %.2e apart\n", i + 1, da, di, dc);
    EXPECT_LT(da, 1e-8);
    EXPECT_LT(di, 1e-8);
    EXPECT_LT(dc, 1e-8);
  }
  EXPECT_EQ(es.measurement.solver.steps, 0);
  EXPECT_EQ(es.measurement.settle_revolutions, ef.measurement.settle_revolutions);
  const SensorConfig clean{0.01, 0.0, 0.0, sensors.sample_rate_hz};
  const BalancingMeasurement m0 = run_balancing_measurement(p, kRotor, 0.0, fast, clean, a, ws);
  EXPECT_EQ(m0.last_revolution_change.maxCoeff(), 0.0);
}

}  // namespace
}  // namespace poise::procedures
