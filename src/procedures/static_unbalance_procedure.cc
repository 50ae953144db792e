#include "procedures/static_unbalance_procedure.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.h"
#include "core/units.h"
#include "procedures/static_unbalance_servo.h"
#include "sampling/normal_stream.h"

namespace poise::procedures {

namespace {
using namespace servo;

void check_plan(const TestPlan& plan) {
  if (plan.positions.size() < 4) throw Error("the static-unbalance test needs at least 4 positions");
  if (!(plan.oscillation.period > 0 && plan.oscillation.periods >= 1)) {
    throw Error("the oscillation needs a positive period and at least one whole period");
  }
  if (!(plan.acquisition.rate_hz > 0)) throw Error("acquisition rate must be positive");
  if (!plan.sweep.empty() && plan.sweep.size() != plan.positions.size()) {
    throw Error("the sweep directions must be given for every position or for none");
  }
}

// The servo's gains and the oscillation, the same at every position.
void set_servo_and_oscillation(Context& c, const TestPlan& plan, const GimbalTruth& truth) {
  const ServoConfig& sv = plan.servo;
  const OscillationConfig& osc = plan.oscillation;
  c.disk = truth.disk;
  const double wc = 2.0 * units::kPi * sv.bandwidth_hz;
  c.kp = sv.inertia_estimate * wc * wc;
  c.kd = 2.0 * sv.damping * sv.inertia_estimate * wc;
  c.ki = c.kp * wc * sv.integral_ratio;
  c.j_ff = sv.inertia_estimate;
  c.kt_nominal = sv.kt_nominal;
  c.kt_true = truth.kt_true;
  c.i_max = sv.current_limit;
  c.omega = 2.0 * units::kPi / osc.period;
  c.rate_amplitude = osc.rate_amplitude;
  c.amplitude = osc.rate_amplitude / c.omega;
  c.centre = osc.centre;
  c.t0 = osc.settle_time;
  c.rhs_calls = 0;
}

// The integration window after the lead-in, the same at every position: [t1, t2] of each
// position's clock, n_samples current samples dt apart, the ADC's resolution lsb.
struct AcquisitionWindow {
  double t1 = 0.0, t2 = 0.0, dt = 0.0, lsb = 0.0;
  long n_samples = 0;
};

AcquisitionWindow acquisition_window(const TestPlan& plan) {
  const OscillationConfig& osc = plan.oscillation;
  const AcquisitionConfig& acq = plan.acquisition;
  AcquisitionWindow w;
  w.lsb = 2.0 * acq.adc_full_scale / std::ldexp(1.0, acq.adc_bits);
  w.t1 = osc.settle_time + osc.lead_in;
  w.t2 = w.t1 + osc.periods * osc.period;
  w.n_samples = static_cast<long>(std::llround(osc.periods * osc.period * acq.rate_hz));
  if (w.n_samples < 2) throw Error("fewer than 2 current samples in the integration window");
  w.dt = (w.t2 - w.t1) / static_cast<double>(w.n_samples);
  return w;
}

// What every position's run shares: the right-hand side's context, the integrator and its
// state layout, the plan and the window.
struct ProcedureRun {
  Context& c;
  solvers::CvodeIntegrator& integ;
  const TestPlan& plan;
  const Disturbances& dist;
  AcquisitionWindow w;
  bool quasi;
  std::size_t n_states, q0, i_servo;  // states; first window integral; the servo's error integral
};

// One position's sensor offset and noise over the window (drawn from the main stream).
struct PositionSensor {
  double t_start = 0.0;          // the test clock at the position's start (s)
  double window_offset = 0.0;    // offset during the window (A)
  double window_noise = 0.0;     // the white noise's mean over the window, in distribution (N(0, 1))
  std::uint64_t sample_key = 0;  // the samples' sub-stream, when sampled
  double drift_mean = 0.0;       // the offset's drift at the samples' mean time (A)
};

// What the window's samples sum to: the measured current and the squared tracking error.
struct WindowSums {
  double sum_i = 0.0, sum_track2 = 0.0;
};

// Locked at the start angle, supports deflected statically, servo integrator empty; then the
// settle and the lead-in (the start transient is not integrated).
void lock_and_settle(const ProcedureRun& run) {
  Context& c = run.c;
  std::array<double, kDynamicStates> y{};
  y[0] = run.plan.oscillation.centre - c.amplitude;
  if (!run.quasi) {
    const auto defl = models::static_deflection(c.disk, c.gravity);
    y[2] = defl[0], y[4] = defl[1];
  }
  run.integ.reset(0.0, std::span<const double>(y.data(), run.n_states));
  run.integ.advance(c.t0, c.t0, false);          // settle (stop at the reference's corner)
  run.integ.advance(run.w.t1, run.w.t1, false);  // lead-in: the start transient is not integrated
}

// The sum of the window's n measured currents from the true current's mean: the sensor's
// offset and drift at the samples' mean time, and the white noise's mean through the ADC drawn
// in distribution, N(0, (sigma^2 + q^2 / 12) / n) (both the integrated and the period-mean window).
double measured_current_sum(const ProcedureRun& run, const PositionSensor& s, double i_mean) {
  const double noise_sigma = run.plan.acquisition.noise_rms, lsb = run.w.lsb;
  const auto n = static_cast<double>(run.w.n_samples);
  const double sigma_mean = std::sqrt((noise_sigma * noise_sigma + lsb * lsb / 12.0) / n);
  return n * (i_mean + s.window_offset + s.drift_mean + sigma_mean * s.window_noise);
}

// The window from its integrals: the current's mean with the noise's mean drawn in
// distribution. Steps to t2; |phi - phi_c| at each step end and at the turning points in between.
WindowSums integrate_window(const ProcedureRun& run, const PositionSensor& s, PositionResult& pr) {
  const Context& c = run.c;
  solvers::CvodeIntegrator& integ = run.integ;
  const double t1 = run.w.t1, t2 = run.w.t2;
  const long n_samples = run.w.n_samples;
  const std::size_t q0 = run.q0;
  auto swing = [&](double phi) { pr.max_abs_phi = std::max(pr.max_abs_phi, std::abs(phi - c.centre)); };
  std::array<double, kDynamicStates> yi{};
  const std::span<double> ybuf(yi.data(), run.n_states);
  double t_prev = integ.time(), w_prev = integ.state()[1];
  swing(integ.state()[0]);
  while (integ.time() < t2) {
    const double t = integ.advance(t2, t2, true);
    const auto st = integ.state();
    swing(st[0]);
    if ((w_prev < 0.0) != (st[1] < 0.0) && st[1] != 0.0) {  // phidot changed sign in this step
      const double ts = t_prev + (t - t_prev) * w_prev / (w_prev - st[1]);
      integ.interpolate(ts, ybuf);
      swing(yi[0]);
    }
    t_prev = t, w_prev = st[1];
  }
  const auto st = integ.state();
  const double window = t2 - t1;
  WindowSums sums;
  sums.sum_i = measured_current_sum(run, s, st[q0] / window);
  sums.sum_track2 = static_cast<double>(n_samples) * st[q0 + 1] / window;
  pr.saturated = st[q0 + 2] > 0.0;
  return sums;
}

// As the instrument samples: n samples from the step interpolants, each through the sensor's
// offset and noise and the ADC; into `record` when given.
WindowSums sample_window(const ProcedureRun& run, const PositionSensor& s, PositionResult& pr,
                         std::vector<RecordSample>* record) {
  const Context& c = run.c;
  solvers::CvodeIntegrator& integ = run.integ;
  const AcquisitionConfig& acq = run.plan.acquisition;
  const Disturbances& dist = run.dist;
  const double t1 = run.w.t1, t2 = run.w.t2, dt = run.w.dt, lsb = run.w.lsb;
  const long n_samples = run.w.n_samples;
  const double noise_sigma = acq.noise_rms;
  const std::size_t n_states = run.n_states, i_servo = run.i_servo;
  const double t_start = s.t_start, window_offset = s.window_offset;
  double sum_i = 0.0, sum_track2 = 0.0;
  sampling::RandomStream sample_stream(s.sample_key, sampling::StreamId::kNoise, 0);
  sampling::NormalStream sample_noise(&sample_stream);
  long k = 0;
  double t = integ.time(), tn = 0.0;
  std::array<double, std::size_t{6} * kDynamicStates> poly{};
  int q = integ.step_polynomial(poly, &tn);
  while (k < n_samples) {
    const double tk = t1 + static_cast<double>(k) * dt;
    if (tk > t) {
      t = integ.advance(t2, t2, true);
      q = integ.step_polynomial(poly, &tn);
      continue;
    }
    // The current only needs phi, phidot and the error integral.
    const double h = tk - tn;
    double yv[3];
    int slot = 0;
    for (std::size_t i : {std::size_t{0}, std::size_t{1}, i_servo}) {
      double v = poly[static_cast<std::size_t>(q) * n_states + i];
      for (int j = q - 1; j >= 0; --j) v = v * h + poly[static_cast<std::size_t>(j) * n_states + i];
      yv[slot++] = v;
    }
    const Reference ref = reference(c, tk);
    const double cmd = commanded_current(c, ref, yv[0], yv[1], yv[2]);
    const double i_true = std::clamp(cmd, -c.i_max, c.i_max);
    pr.saturated = pr.saturated || i_true != cmd;
    // Sensor: offset and white noise, then the ADC's range and resolution.
    const double drift = dist.offset_drift_rate * (t_start + tk);
    double i_meas = i_true + window_offset + drift + (noise_sigma > 0 ? noise_sigma * sample_noise.next() : 0.0);
    i_meas = std::clamp(std::round(i_meas / lsb) * lsb, -acq.adc_full_scale, acq.adc_full_scale);
    sum_i += i_meas;
    if (record) record->push_back({tk - t1, i_meas, yv[0]});
    const double e = ref.phi - yv[0];
    sum_track2 += e * e;
    pr.max_abs_phi = std::max(pr.max_abs_phi, std::abs(yv[0] - c.centre));
    ++k;
  }
  return {sum_i, sum_track2};
}

// The period-mean model of one position (PositionModel::kPeriodMean): the mean true current
// over whole periods of the reference; false if the drive would saturate somewhere on the way.
bool period_mean_current(const Context& c, double* i_mean) {
  const models::DiskRotorParams& d = c.disk;
  const double j_total = d.inertia + d.mass * d.eccentricity * d.eccentricity;
  const double swing = std::abs(c.amplitude) * std::max(models::highest_cogging_order(d), 1);
  const int points = 2 * (32 + static_cast<int>(std::ceil(swing)));  // even: the grid is symmetric
  double sum = 0.0;
  for (int j = 0; j < points; ++j) {
    const double th = 2.0 * units::kPi * j / points;
    const double phi = c.centre - c.amplitude * std::cos(th);
    const double rate = c.rate_amplitude * std::sin(th);
    const double acc = c.rate_amplitude * c.omega * std::cos(th);
    const double q = j_total * models::rigid_axis_acceleration(d, c.gravity, phi, rate, 0.0);
    const double i = (j_total * acc - q - c.disturbance_torque) / c.kt_true;
    if (std::abs(i) >= c.i_max) return false;
    sum += i;
  }
  *i_mean = sum / points;
  return true;
}

// The window on the period-mean model: the same sums as integrate_window, with the current's
// mean from period_mean_current.
WindowSums period_mean_window(const ProcedureRun& run, const PositionSensor& s, double i_mean, PositionResult& pr) {
  pr.max_abs_phi = std::abs(run.c.amplitude);
  WindowSums sums;
  sums.sum_i = measured_current_sum(run, s, i_mean);
  return sums;
}

// One position's start: its true angle, the sensor's offset and the window noise drawn (the
// same five draws per position on either acquisition path), gravity in the gimbal frame and the
// disturbance torque set in the context. `offset` carries the offset's random walk.
PositionSensor start_position(const ProcedureRun& run, const GimbalTruth& truth, std::size_t ip, double duration,
                              double& offset, sampling::NormalStream& normal, sampling::RandomStream& noise,
                              PositionResult& pr) {
  const TestPlan& plan = run.plan;
  const AcquisitionConfig& acq = plan.acquisition;
  const Disturbances& dist = run.dist;
  Context& c = run.c;
  pr.theta_nominal = plan.positions[ip];
  pr.sweep = plan.sweep.empty() ? 1 : plan.sweep[ip];
  PositionSensor s;
  s.t_start = static_cast<double>(ip) * duration + plan.move_time;  // test clock
  pr.time = s.t_start + 0.5 * (run.w.t1 + run.w.t2);
  pr.theta_true = pr.theta_nominal + truth.turntable_zero + plan.positioning_error * normal.next();
  offset += acq.offset_drift * normal.next();
  s.window_offset = offset + acq.offset_noise * normal.next();
  s.window_noise = normal.next();    // the white noise's mean, in distribution
  s.sample_key = noise.next_bits();  // its samples' sub-stream otherwise
  c.gravity = models::gravity_in_gimbal(plan.gravity, pr.theta_true, truth.axis_tilt, truth.axis_tilt_azimuth);
  c.disturbance_torque = dist.harmonic2_torque * std::sin(2.0 * pr.theta_true + dist.harmonic2_phase) +
                         dist.direction_torque * pr.sweep +
                         (static_cast<int>(ip) == dist.bump_position ? dist.bump_torque : 0.0);
  // Drift of the offset over the window: linear, so its mean is its value at the samples'
  // mean time t_start + t1 + (n - 1) dt / 2.
  s.drift_mean =
      dist.offset_drift_rate * (s.t_start + run.w.t1 + 0.5 * static_cast<double>(run.w.n_samples - 1) * run.w.dt);
  return s;
}

}  // namespace

MeasurementResult run_static_unbalance_procedure(const TestPlan& plan, const GimbalTruth& truth,
                                                 sampling::RandomStream& noise, StaticUnbalanceWorkspace& ws,
                                                 int record_position, std::vector<RecordSample>* record) {
  check_plan(plan);
  Context& c = ws.context();
  const bool quasi = plan.supports == Supports::kQuasiStatic;
  solvers::CvodeIntegrator& integ = ws.integrator(plan.supports);
  const std::size_t n_states = integ.size();
  set_servo_and_oscillation(c, plan, truth);
  const AcquisitionConfig& acq = plan.acquisition;
  const Disturbances& dist = truth.disturbances;
  const ProcedureRun run{c,
                         integ,
                         plan,
                         dist,
                         acquisition_window(plan),
                         quasi,
                         n_states,
                         n_states - kQuadratures,
                         quasi ? std::size_t{2} : std::size_t{6}};
  const double t1 = run.w.t1, t2 = run.w.t2;
  c.t1 = t1;
  sampling::NormalStream normal(&noise);

  MeasurementResult out;
  out.positions.reserve(plan.positions.size());
  double offset = acq.offset;
  std::vector<double> theta, torque;
  theta.reserve(plan.positions.size());
  torque.reserve(plan.positions.size());
  const double duration = position_duration(plan);  // move and lock, then the test
  if (record) record->clear();
  for (std::size_t ip = 0; ip < plan.positions.size(); ++ip) {
    PositionResult pr;
    const PositionSensor s = start_position(run, truth, ip, duration, offset, normal, noise, pr);
    const long n_samples = run.w.n_samples;
    const double noise_sigma = acq.noise_rms;
    const bool recorded = record != nullptr && static_cast<int>(ip) == record_position;
    const bool sampled = recorded || noise_sigma < run.w.lsb ||
                         c.i_max + std::abs(s.window_offset) + std::abs(s.drift_mean) +
                                 std::abs(dist.offset_drift_rate) * (t2 - t1) + 6.0 * noise_sigma >=
                             acq.adc_full_scale;
    double i_mean = 0.0;
    const bool period_mean =
        !sampled && plan.position_model == PositionModel::kPeriodMean && period_mean_current(c, &i_mean);
    if (!period_mean) lock_and_settle(run);
    const WindowSums sums = period_mean ? period_mean_window(run, s, i_mean, pr)
                            : sampled   ? sample_window(run, s, pr, recorded ? record : nullptr)
                                        : integrate_window(run, s, pr);
    const double mean_i = sums.sum_i / static_cast<double>(n_samples);
    pr.torque = plan.servo.kt_nominal * mean_i;  // Eq. 21 with the nominal K_T
    pr.rms_tracking = std::sqrt(sums.sum_track2 / static_cast<double>(n_samples));
    if (!period_mean) {
      const solvers::CvodeStats st = integ.stats();
      out.solver.steps += st.steps;
      out.solver.rhs_evals += st.rhs_evals;
      out.solver.jac_evals += st.jac_evals;
    }
    theta.push_back(pr.theta_nominal);
    torque.push_back(pr.torque);
    out.positions.push_back(pr);
  }
  out.fit = estimators::fit_sine(theta, torque);
  return out;
}

}  // namespace poise::procedures
