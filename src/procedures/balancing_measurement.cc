#include "procedures/balancing_measurement.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include "core/error.h"
#include "core/units.h"
#include "sampling/normal_stream.h"

namespace poise::procedures {

using cd = std::complex<double>;

struct BalancingWorkspace::Context {
  models::SpringPlateRhsData data;
  std::array<double, 4> scale{1.0, 1.0, 1.0, 1.0};  // state = scale * integrated state
};

namespace {
using BalancingContext = BalancingWorkspace::Context;
constexpr int kStates = 4;  // x, x', theta, theta'

// spring_plate_rhs on states scaled to O(1), so that one atol suits responses of any size.
int scaled_rhs(double t, const double* ys, double* ydot, void* user) {
  if (user == nullptr) return -1;
  auto* c = static_cast<BalancingContext*>(user);
  double y[kStates];
  for (std::size_t i = 0; i < kStates; ++i) y[i] = ys[i] * c->scale[i];
  const int r = models::spring_plate_rhs(t, y, ydot, &c->data);
  for (std::size_t i = 0; i < kStates; ++i) ydot[i] /= c->scale[i];
  return r;
}

}  // namespace

BalancingWorkspace::BalancingWorkspace(const solvers::CvodeOptions& opt)
    : ctx_(std::make_unique<Context>()),
      integrator_(std::make_unique<solvers::CvodeIntegrator>(kStates, scaled_rhs, ctx_.get(), opt)) {}

BalancingWorkspace::~BalancingWorkspace() = default;  // the integrator first, then its context

cd demodulate(std::span<const double> samples, std::span<const double> shaft_angles) {
  require(samples.size() == shaft_angles.size(), "demodulate: samples and shaft angles differ in length");
  require(!samples.empty(), "demodulate: no samples");
  double a = 0.0, b = 0.0;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    a += samples[k] * std::cos(shaft_angles[k]);
    b += samples[k] * std::sin(shaft_angles[k]);
  }
  const double f = 2.0 / static_cast<double>(samples.size());
  return {f * a, -f * b};
}

double slowest_decay_rate(const models::SpringPlateMachineParams& p) {
  models::validate(p);
  const Eigen::Matrix2d minv = models::mass_matrix(p).inverse();
  Eigen::Matrix4d a = Eigen::Matrix4d::Zero();
  a.block<2, 2>(0, 2) = Eigen::Matrix2d::Identity();
  a.block<2, 2>(2, 0) = -minv * models::stiffness_matrix(p);
  a.block<2, 2>(2, 2) = -minv * models::damping_matrix(p);
  Eigen::EigenSolver<Eigen::Matrix4d> es(a, false);
  require(es.info() == Eigen::Success, "balancing measurement: eigenvalues of the state matrix failed");
  double sigma = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kStates; ++i) sigma = std::min(sigma, -es.eigenvalues()(i).real());
  require(sigma > 0.0,
          "balancing measurement: the machine is undamped (damping_x, damping_theta); the start "
          "transient never decays and no steady state is reached");
  return sigma;
}

namespace {

void check_run(const BalancingRunConfig& run, const SensorConfig& sensors) {
  require(run.speed_rpm > 0.0, "balancing measurement: speed_rpm must be > 0");
  require(run.revolutions >= 2, "balancing measurement: at least 2 whole revolutions (settling check)");
  require(run.settle_time_constants >= 0.0 && run.min_settle_revolutions >= 0,
          "balancing measurement: settling must not be negative");
  require(sensors.sample_rate_hz > 0.0 && sensors.noise_rms >= 0.0,
          "balancing measurement: sample rate must be > 0 and noise rms >= 0");
}

// The run's timing into `out`: speed, settling (whole revolutions, from the slowest decay)
// and samples per revolution.
void set_timing(const models::SpringPlateMachineParams& machine, const BalancingRunConfig& run,
                const SensorConfig& sensors, BalancingMeasurement& out) {
  const double omega = models::rpm_to_rad_per_s(run.speed_rpm);
  const double period = 2.0 * units::kPi / omega;
  out.omega = omega;
  const double sigma = slowest_decay_rate(machine);
  out.decay_time_constant = 1.0 / sigma;
  out.settle_revolutions =
      std::max(run.min_settle_revolutions, static_cast<int>(std::ceil(run.settle_time_constants / sigma / period)));
  out.settle_time = out.settle_revolutions * period;
  const double spr_real = std::round(sensors.sample_rate_hz * period);
  require(spr_real >= 3.0 && spr_real < 1e8, "balancing measurement: need 3 or more samples per revolution");
  out.samples_per_revolution = static_cast<int>(spr_real);
}

// Scale the states by the size of the exact steady state (a floor for a zero unbalance).
void scale_states(BalancingContext& c, const models::SpringPlateMachineParams& machine,
                  const models::SpringPlateUnbalance& unbalance, double omega) {
  c.data = {machine, unbalance, omega};
  const Eigen::Vector2cd xs = models::steady_state_response(machine, unbalance, omega);
  models::SpringPlateUnbalance unit;
  unit.static_unbalance = 1e-9;
  unit.couple_unbalance = 1e-9;
  const Eigen::Vector2cd floor = models::hard_bearing_response(machine, unit, omega);
  const double w2 = models::natural_frequencies(machine).omega_2;
  c.scale[0] = std::max(std::abs(xs(0)), std::abs(floor(0)));
  c.scale[2] = std::max(std::abs(xs(1)), std::abs(floor(1)));
  c.scale[1] = w2 * c.scale[0];
  c.scale[3] = w2 * c.scale[2];
}

// The sampled window: `revolutions` whole revolutions from t1 to t2, spr samples dt apart in each.
struct SampleWindow {
  double t1 = 0.0, t2 = 0.0, period = 0.0, dt = 0.0;
  int spr = 0, revolutions = 0;
  long n_samples = 0;
};

// Each sensor reads its own plate as built: sensor 1 the horizontal plate that carries it
// (k5,1), sensor 2 the torsional plate's force (its end condition's share of k6 l theta).
struct SensorReadout {
  double k5 = 0.0, k6l = 0.0, g1 = 1.0, g2 = 1.0;
};

SensorReadout sensor_readout(const models::SpringPlateMachineParams& machine, const SensorConfig& sensors) {
  SensorReadout r;
  r.k5 = machine.sensor_1_plate_stiffness > 0.0 ? machine.sensor_1_plate_stiffness : machine.horizontal_plate_stiffness;
  r.k6l = machine.torsion_split.force_factor * machine.torsional_plate_stiffness * machine.lever;
  r.g1 = 1.0 + sensors.gain_error_1;
  r.g2 = 1.0 + sensors.gain_error_2;
  return r;
}

// Sums e^{-i phi} s over the window and over each of the last two revolutions.
struct DemodulationSums {
  cd sum1 = 0.0, sum2 = 0.0;
  std::array<cd, 2> rev1{}, rev2{};  // [0] = previous revolution, [1] = last
};

DemodulationSums sample_and_demodulate(solvers::CvodeIntegrator& integ, const BalancingContext& c,
                                       const SampleWindow& w, const SensorReadout& r, const SensorConfig& sensors,
                                       sampling::NormalStream& normal) {
  const double t1 = w.t1, t2 = w.t2, period = w.period, dt = w.dt;
  const int spr = w.spr;
  const long n_samples = w.n_samples;
  const double k5 = r.k5, k6l = r.k6l, g1 = r.g1, g2 = r.g2;
  const int revolutions = w.revolutions;
  cd sum1 = 0.0, sum2 = 0.0;
  std::array<cd, 2> rev1{}, rev2{};  // [0] = previous revolution, [1] = last
  std::array<double, kStates> y{};
  double t = integ.time();
  long k = 0;
  while (k < n_samples) {
    const long rev = k / spr, j = k % spr;
    const double tk = t1 + static_cast<double>(rev) * period + static_cast<double>(j) * dt;
    if (tk > t) {
      t = integ.advance(t2, t2, true);
      continue;
    }
    integ.interpolate(tk, y);
    double f1 = g1 * k5 * (y[0] * c.scale[0] + sensors.sensor_1_offset * y[2] * c.scale[2]);
    double f2 = g2 * k6l * y[2] * c.scale[2];
    if (sensors.noise_rms > 0.0) {
      f1 += sensors.noise_rms * normal.next();
      f2 += sensors.noise_rms * normal.next();
    }
    // Shaft angle from the encoder: whole revolutions drop out, j dt omega = 2 pi j / spr.
    const cd e = std::polar(1.0, -2.0 * units::kPi * static_cast<double>(j) / spr);
    sum1 += f1 * e;
    sum2 += f2 * e;
    if (rev >= revolutions - 2) {
      const auto ri = static_cast<std::size_t>(rev - (revolutions - 2));
      rev1[ri] += f1 * e;
      rev2[ri] += f2 * e;
    }
    ++k;
  }
  return {sum1, sum2, rev1, rev2};
}

// The fast model's window: the sensors read the exact steady state. Sampled over whole
// revolutions it demodulates exactly to the sensor's complex amplitude (the shaft angle at
// t1 is a whole number of turns), so only the noise is sampled, with the draws of the
// integrated run in the same order.
DemodulationSums steady_state_sums(const models::SpringPlateMachineParams& machine,
                                   const models::SpringPlateUnbalance& unbalance, double omega, const SampleWindow& w,
                                   const SensorReadout& r, const SensorConfig& sensors,
                                   sampling::NormalStream& normal) {
  const Eigen::Vector2cd x = models::steady_state_response(machine, unbalance, omega);
  const cd a1 = r.g1 * r.k5 * (x(0) + sensors.sensor_1_offset * x(1));
  const cd a2 = r.g2 * r.k6l * x(1);
  const double half = 0.5 * static_cast<double>(w.n_samples), half_rev = 0.5 * w.spr;
  DemodulationSums s{a1 * half, a2 * half, {a1 * half_rev, a1 * half_rev}, {a2 * half_rev, a2 * half_rev}};
  if (!(sensors.noise_rms > 0.0)) return s;
  std::vector<cd> turn(static_cast<std::size_t>(w.spr));
  for (int j = 0; j < w.spr; ++j) turn[static_cast<std::size_t>(j)] = std::polar(1.0, -2.0 * units::kPi * j / w.spr);
  for (long k = 0; k < w.n_samples; ++k) {
    const long rev = k / w.spr;
    const cd e = turn[static_cast<std::size_t>(k % w.spr)];
    const double n1 = sensors.noise_rms * normal.next();
    const double n2 = sensors.noise_rms * normal.next();
    s.sum1 += n1 * e;
    s.sum2 += n2 * e;
    if (rev >= w.revolutions - 2) {
      const auto ri = static_cast<std::size_t>(rev - (w.revolutions - 2));
      s.rev1[ri] += n1 * e;
      s.rev2[ri] += n2 * e;
    }
  }
  return s;
}

}  // namespace

BalancingMeasurement run_balancing_measurement(const models::SpringPlateMachineParams& machine,
                                               const models::SpringPlateUnbalance& unbalance,
                                               const BalancingRunConfig& run, const SensorConfig& sensors,
                                               sampling::RandomStream& noise, BalancingWorkspace& ws) {
  check_run(run, sensors);
  BalancingMeasurement out;
  set_timing(machine, run, sensors, out);
  const double period = 2.0 * units::kPi / out.omega;
  const int spr = out.samples_per_revolution;

  SampleWindow w;
  w.t1 = out.settle_time;
  w.t2 = w.t1 + run.revolutions * period;
  w.period = period;
  w.spr = spr;
  w.revolutions = run.revolutions;
  w.n_samples = static_cast<long>(run.revolutions) * spr;
  w.dt = period / spr;
  sampling::NormalStream normal(&noise);
  const SensorReadout readout = sensor_readout(machine, sensors);
  DemodulationSums s;
  if (run.response == BalancingResponse::kSteadyState) {
    s = steady_state_sums(machine, unbalance, out.omega, w, readout, sensors, normal);
  } else {
    BalancingContext& c = ws.context();
    scale_states(c, machine, unbalance, out.omega);
    solvers::CvodeIntegrator& integ = ws.integrator();
    const std::array<double, kStates> y0{};
    integ.reset(0.0, y0);  // zeroes the solver's counters
    if (w.t1 > 0.0) {
      integ.advance(w.t1, w.t1, false);  // settle: start transient
    } else {
      integ.advance(w.t2, w.t2, true);  // one step, so that the interpolant exists at t = 0
    }
    s = sample_and_demodulate(integ, c, w, readout, sensors, normal);
    out.solver = integ.stats();
  }
  out.amplitudes = Eigen::Vector2cd(s.sum1, s.sum2) * (2.0 / static_cast<double>(w.n_samples));
  const double per_rev = 2.0 / spr;
  out.last_revolution_change(0) = std::abs(s.rev1[1] - s.rev1[0]) * per_rev / std::abs(out.amplitudes(0));
  out.last_revolution_change(1) = std::abs(s.rev2[1] - s.rev2[0]) * per_rev / std::abs(out.amplitudes(1));
  return out;
}

BalancingMeasurement run_balancing_measurement(const models::SpringPlateMachineParams& machine,
                                               std::span<const models::PlaneMass> masses, double reference_height,
                                               const BalancingRunConfig& run, const SensorConfig& sensors,
                                               sampling::RandomStream& noise, BalancingWorkspace& ws) {
  const models::SpringPlateUnbalance u =
      models::to_machine_unbalance(models::resultant_unbalance(masses, reference_height));
  return run_balancing_measurement(machine, u, run, sensors, noise, ws);
}

// ---- estimators -----------------------------------------------------------------------------

Eigen::Vector2cd split_to_planes(cd u, cd v, double height, const CorrectionPlanes& planes) {
  const double span = planes.height_2 - planes.height_1;
  require(span != 0.0, "split to planes: the two correction planes are at the same height");
  const cd u2 = (v - u * (planes.height_1 - height)) / span;
  return {u - u2, u2};
}

ClosedFormEstimate closed_form_estimate(const models::SpringPlateMachineParams& machine,
                                        const Eigen::Vector2cd& amplitudes, double omega, double height,
                                        const CorrectionPlanes& planes) {
  ClosedFormEstimate e;
  e.machine = models::unbalance_from_sensor_forces(machine, amplitudes, omega, height);
  e.static_unbalance = std::polar(e.machine.static_unbalance, e.machine.static_phase);
  e.couple_unbalance = std::polar(e.machine.couple_unbalance, e.machine.couple_phase);
  e.height = height;
  e.planes = split_to_planes(e.static_unbalance, e.couple_unbalance, height, planes);
  return e;
}

InfluenceCalibration calibrate_influence(const Eigen::Vector2cd& bare, const Eigen::Vector2cd& with_test_1, cd test_1,
                                         const Eigen::Vector2cd& with_test_2, cd test_2) {
  require(test_1 != 0.0 && test_2 != 0.0, "influence calibration: a test mass is zero");
  InfluenceCalibration cal;
  cal.coefficients.col(0) = (with_test_1 - bare) / test_1;
  cal.coefficients.col(1) = (with_test_2 - bare) / test_2;
  const Eigen::Matrix2cd& c = cal.coefficients;
  const double det = std::abs(c(0, 0) * c(1, 1) - c(0, 1) * c(1, 0));
  const double size = std::abs(c(0, 0) * c(1, 1)) + std::abs(c(0, 1) * c(1, 0));
  require(det > 1e-9 * size,
          "influence calibration: influence matrix is singular (test planes too close or no effect)");
  cal.bare_amplitudes = bare;
  cal.bare_unbalance = c.partialPivLu().solve(bare);
  return cal;
}

Eigen::Vector2cd influence_estimate(const InfluenceCalibration& cal, const Eigen::Vector2cd& amplitudes) {
  return cal.coefficients.partialPivLu().solve(amplitudes);
}

UnbalanceEstimates estimate_unbalance(const models::SpringPlateMachineParams& machine,
                                      std::span<const models::PlaneMass> calibration_rotor,
                                      const models::PlaneMass& test_1, const models::PlaneMass& test_2,
                                      std::span<const models::PlaneMass> rotor, double reference_height,
                                      const BalancingRunConfig& run, const SensorConfig& sensors,
                                      sampling::RandomStream& noise, BalancingWorkspace& ws) {
  UnbalanceEstimates out;
  std::vector<models::PlaneMass> masses(calibration_rotor.begin(), calibration_rotor.end());
  out.calibration_runs.push_back(run_balancing_measurement(machine, masses, reference_height, run, sensors, noise, ws));
  masses.push_back(test_1);
  out.calibration_runs.push_back(run_balancing_measurement(machine, masses, reference_height, run, sensors, noise, ws));
  masses.back() = test_2;
  out.calibration_runs.push_back(run_balancing_measurement(machine, masses, reference_height, run, sensors, noise, ws));
  const auto unb = [](const models::PlaneMass& m) { return m.mass * m.radius * std::polar(1.0, m.angle); };
  out.calibration = calibrate_influence(out.calibration_runs[0].amplitudes, out.calibration_runs[1].amplitudes,
                                        unb(test_1), out.calibration_runs[2].amplitudes, unb(test_2));
  out.measurement = run_balancing_measurement(machine, rotor, reference_height, run, sensors, noise, ws);
  out.influence = influence_estimate(out.calibration, out.measurement.amplitudes);
  out.closed_form = closed_form_estimate(machine, out.measurement.amplitudes, out.measurement.omega, reference_height,
                                         {test_1.height, test_2.height});
  return out;
}

}  // namespace poise::procedures
