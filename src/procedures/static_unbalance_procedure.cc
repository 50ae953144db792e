#include "procedures/static_unbalance_procedure.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/units.h"
#include "sampling/normal_stream.h"

namespace poise::procedures {

struct StaticUnbalanceWorkspace::Context {
  models::DiskRotorParams disk;
  models::GimbalGravity gravity;
  double kp = 0, kd = 0, ki = 0, j_ff = 0, kt_nominal = 1, kt_true = 1, i_max = 1;
  double disturbance_torque = 0;  // constant external torque at this position (N m)
  double t0 = 0, omega = 1, amplitude = 0, rate_amplitude = 0, centre = 0;
  double t1 = 0;                  // start of the integration window (s)
  long rhs_calls = 0;
};

namespace {
using Context = StaticUnbalanceWorkspace::Context;
// States. Dynamic supports: phi, phidot, y, ydot, z, zdot, integral of the angle error;
// quasi-static: phi, phidot, integral of the angle error. Then, both, three window integrals:
// current, squared tracking error, clipped excess of the commanded current.
constexpr int kDynamicStates = 10, kQuasiStates = 6, kQuadratures = 3;

struct Reference {
  double phi, rate, acc;
};

// phi_ref = phi_c - a cos(w (t - t0)) after t0 (so phidot_ref = A sin(...)), held before.
inline Reference reference(const Context& c, double t) {
  if (t < c.t0) return {c.centre - c.amplitude, 0.0, 0.0};
  const double w = c.omega * (t - c.t0);
  return {c.centre - c.amplitude * std::cos(w), c.rate_amplitude * std::sin(w),
          c.rate_amplitude * c.omega * std::cos(w)};
}

// Commanded amplifier current: PID plus acceleration feed-forward (before the limit).
inline double commanded_current(const Context& c, const Reference& r, double phi, double phidot, double integral) {
  return (c.kp * (r.phi - phi) + c.kd * (r.rate - phidot) + c.ki * integral + c.j_ff * r.acc) / c.kt_nominal;
}

// The servo integral and the window integrals of both formulations (q: their first index).
inline void servo_and_window(const Context& c, double t, const Reference& r, double phi, double cmd, double i,
                             double* servo_dot, double* q_dot) {
  // Conditional integration: the integrator holds while the amplifier saturates.
  *servo_dot = i != cmd ? 0.0 : r.phi - phi;
  const bool in_window = t >= c.t1;
  const double e = r.phi - phi;
  q_dot[0] = in_window ? i : 0.0;
  q_dot[1] = in_window ? e * e : 0.0;
  q_dot[2] = in_window ? std::max(std::abs(cmd) - c.i_max, 0.0) : 0.0;
}

int rhs_dynamic(double t, const double* y, double* ydot, void* user) {
  auto* c = static_cast<Context*>(user);
  ++c->rhs_calls;
  const Reference r = reference(*c, t);
  const double cmd = commanded_current(*c, r, y[0], y[1], y[6]);
  const double i = std::clamp(cmd, -c->i_max, c->i_max);
  const models::DiskState s{y[0], y[1], y[2], y[3], y[4], y[5]};
  const auto acc = models::disk_accelerations(c->disk, c->gravity, s, c->kt_true * i + c->disturbance_torque);
  ydot[0] = y[1];
  ydot[1] = acc[0];
  ydot[2] = y[3];
  ydot[3] = acc[1];
  ydot[4] = y[5];
  ydot[5] = acc[2];
  servo_and_window(*c, t, r, y[0], cmd, i, &ydot[6], &ydot[7]);
  for (int k = 0; k < kDynamicStates; ++k) {
    if (!std::isfinite(ydot[k])) return 1;  // recoverable: CVODE retries a smaller step
  }
  return 0;
}

int rhs_quasi_static(double t, const double* y, double* ydot, void* user) {
  auto* c = static_cast<Context*>(user);
  ++c->rhs_calls;
  const Reference r = reference(*c, t);
  const double cmd = commanded_current(*c, r, y[0], y[1], y[2]);
  const double i = std::clamp(cmd, -c->i_max, c->i_max);
  ydot[0] = y[1];
  ydot[1] = models::rigid_axis_acceleration(c->disk, c->gravity, y[0], y[1], c->kt_true * i + c->disturbance_torque);
  servo_and_window(*c, t, r, y[0], cmd, i, &ydot[2], &ydot[3]);
  for (int k = 0; k < kQuasiStates; ++k) {
    if (!std::isfinite(ydot[k])) return 1;
  }
  return 0;
}

// Absolute tolerances: the model's per-state ones for the mechanical states (7, the dynamic
// order), then the window integrals: the current's tight enough that its mean is good to
// 1e-3 rtol of the current limit; the tracking and excess integrals are diagnostics, left
// out of the error test (a huge tolerance).
solvers::CvodeOptions extended_options(solvers::CvodeOptions opt, Supports supports, double i_scale) {
  std::vector<double> mech = opt.atol_per_state;
  if (mech.size() != 7) mech.assign(7, opt.atol);
  std::vector<double> a;
  if (supports == Supports::kDynamic) {
    a = mech;
  } else {
    a = {mech[0], mech[1], mech[6]};
  }
  a.push_back(1e-3 * opt.rtol * i_scale);  // A s
  a.push_back(1e30);
  a.push_back(1e30);
  opt.atol_per_state = a;
  return opt;
}

}  // namespace

StaticUnbalanceWorkspace::StaticUnbalanceWorkspace(const solvers::CvodeOptions& opt)
    : opt_(opt), ctx_(std::make_unique<Context>()) {}

StaticUnbalanceWorkspace::~StaticUnbalanceWorkspace() = default;

solvers::CvodeIntegrator& StaticUnbalanceWorkspace::integrator(Supports supports) {
  // The current's tolerance scale: 1 A (the window integrals are in A s); CvodeOptions are
  // the model's, fixed for the workspace's life.
  if (supports == Supports::kDynamic) {
    if (dynamic_ == nullptr) {
      dynamic_ = std::make_unique<solvers::CvodeIntegrator>(kDynamicStates, rhs_dynamic, ctx_.get(),
                                                            extended_options(opt_, supports, 1.0));
    }
    return *dynamic_;
  }
  if (quasi_static_ == nullptr) {
    quasi_static_ = std::make_unique<solvers::CvodeIntegrator>(kQuasiStates, rhs_quasi_static, ctx_.get(),
                                                               extended_options(opt_, supports, 1.0));
  }
  return *quasi_static_;
}

MeasurementResult run_static_unbalance_procedure(const TestPlan& plan, const GimbalTruth& truth,
                                            sampling::RandomStream& noise,
                                            StaticUnbalanceWorkspace& ws, int record_position,
                                            std::vector<RecordSample>* record) {
  if (plan.positions.size() < 4) throw Error("the static-unbalance test needs at least 4 positions");
  if (!(plan.oscillation.period > 0 && plan.oscillation.periods >= 1)) {
    throw Error("the oscillation needs a positive period and at least one whole period");
  }
  if (!(plan.acquisition.rate_hz > 0)) throw Error("acquisition rate must be positive");
  if (!plan.sweep.empty() && plan.sweep.size() != plan.positions.size()) {
    throw Error("the sweep directions must be given for every position or for none");
  }
  Context& c = ws.context();
  const bool quasi = plan.supports == Supports::kQuasiStatic;
  solvers::CvodeIntegrator& integ = ws.integrator(plan.supports);
  const std::size_t n_states = integ.size();
  const std::size_t q0 = n_states - kQuadratures;   // first window integral
  const std::size_t i_servo = quasi ? 2 : 6;        // the servo's error integral
  const ServoConfig& sv = plan.servo;
  const OscillationConfig& osc = plan.oscillation;
  const AcquisitionConfig& acq = plan.acquisition;
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

  sampling::NormalStream normal(&noise);
  const double lsb = 2.0 * acq.adc_full_scale / std::ldexp(1.0, acq.adc_bits);
  const double t1 = osc.settle_time + osc.lead_in;
  const double t2 = t1 + osc.periods * osc.period;
  c.t1 = t1;
  const auto n_samples = static_cast<long>(std::llround(osc.periods * osc.period * acq.rate_hz));
  if (n_samples < 2) throw Error("fewer than 2 current samples in the integration window");
  const double dt = (t2 - t1) / static_cast<double>(n_samples);

  MeasurementResult out;
  out.positions.reserve(plan.positions.size());
  double offset = acq.offset;
  std::array<double, kDynamicStates> y{};
  std::vector<double> theta, torque;
  theta.reserve(plan.positions.size());
  torque.reserve(plan.positions.size());
  const Disturbances& dist = truth.disturbances;
  const double duration = position_duration(plan);  // move and lock, then the test
  if (record) record->clear();
  for (std::size_t ip = 0; ip < plan.positions.size(); ++ip) {
    const double theta_nominal = plan.positions[ip];
    PositionResult pr;
    pr.theta_nominal = theta_nominal;
    pr.sweep = plan.sweep.empty() ? 1 : plan.sweep[ip];
    const double t_start = static_cast<double>(ip) * duration + plan.move_time;  // test clock
    pr.time = t_start + 0.5 * (t1 + t2);
    // The main stream: the same five draws per position on either acquisition path.
    pr.theta_true = theta_nominal + truth.turntable_zero + plan.positioning_error * normal.next();
    offset += acq.offset_drift * normal.next();
    const double window_offset = offset + acq.offset_noise * normal.next();
    const double window_noise = normal.next();          // the white noise's mean, in distribution
    const std::uint64_t sample_key = noise.next_bits();  // its samples' sub-stream otherwise
    c.gravity = models::gravity_in_gimbal(plan.gravity, pr.theta_true, truth.axis_tilt,
                                          truth.axis_tilt_azimuth);
    c.disturbance_torque = dist.harmonic2_torque * std::sin(2.0 * pr.theta_true + dist.harmonic2_phase) +
                           dist.direction_torque * pr.sweep +
                           (static_cast<int>(ip) == dist.bump_position ? dist.bump_torque : 0.0);
    // Locked at the start angle, supports deflected statically, servo integrator empty.
    y.fill(0.0);
    y[0] = osc.centre - c.amplitude;
    if (!quasi) {
      const auto defl = models::static_deflection(c.disk, c.gravity);
      y[2] = defl[0], y[4] = defl[1];
    }
    integ.reset(0.0, std::span<const double>(y.data(), n_states));
    integ.advance(c.t0, c.t0, false);  // settle (stop at the reference's corner)
    integ.advance(t1, t1, false);      // lead-in: the start transient is not integrated
    // Drift of the offset over the window: linear, so its mean is its value at the samples'
    // mean time t_start + t1 + (n - 1) dt / 2.
    const double drift_mean = dist.offset_drift_rate * (t_start + t1 + 0.5 * static_cast<double>(n_samples - 1) * dt);
    const double noise_sigma = acq.noise_rms;
    const bool sampled = (record != nullptr && static_cast<int>(ip) == record_position) || noise_sigma < lsb ||
                         c.i_max + std::abs(window_offset) + std::abs(drift_mean) +
                                 std::abs(dist.offset_drift_rate) * (t2 - t1) + 6.0 * noise_sigma >=
                             acq.adc_full_scale;
    double sum_i = 0.0, sum_track2 = 0.0;
    if (!sampled) {
      // Step to t2; |phi - phi_c| at each step end and at the turning points in between.
      auto swing = [&](double phi) { pr.max_abs_phi = std::max(pr.max_abs_phi, std::abs(phi - c.centre)); };
      std::array<double, kDynamicStates> yi{};
      const std::span<double> ybuf(yi.data(), n_states);
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
      const double i_mean = st[q0] / window;
      const double sigma_mean = std::sqrt((noise_sigma * noise_sigma + lsb * lsb / 12.0) / static_cast<double>(n_samples));
      sum_i = static_cast<double>(n_samples) * (i_mean + window_offset + drift_mean + sigma_mean * window_noise);
      sum_track2 = static_cast<double>(n_samples) * st[q0 + 1] / window;
      pr.saturated = st[q0 + 2] > 0.0;
    } else {
      // As the instrument samples: n samples from the step interpolants.
      sampling::RandomStream sample_stream(sample_key, sampling::StreamId::kNoise, 0);
      sampling::NormalStream sample_noise(&sample_stream);
      long k = 0;
      double t = integ.time(), tn = 0.0;
      std::array<double, 6 * kDynamicStates> poly{};
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
        if (record && static_cast<int>(ip) == record_position) record->push_back({tk - t1, i_meas, yv[0]});
        const double e = ref.phi - yv[0];
        sum_track2 += e * e;
        pr.max_abs_phi = std::max(pr.max_abs_phi, std::abs(yv[0] - c.centre));
        ++k;
      }
    }
    const double mean_i = sum_i / static_cast<double>(n_samples);
    pr.torque = sv.kt_nominal * mean_i;  // Eq. 21 with the nominal K_T
    pr.rms_tracking = std::sqrt(sum_track2 / static_cast<double>(n_samples));
    const solvers::CvodeStats st = integ.stats();
    out.solver.steps += st.steps;
    out.solver.rhs_evals += st.rhs_evals;
    out.solver.jac_evals += st.jac_evals;
    theta.push_back(theta_nominal);
    torque.push_back(pr.torque);
    out.positions.push_back(pr);
  }
  out.fit = estimators::fit_sine(theta, torque);
  return out;
}

Placement parse_placement(const std::string& name) {
  if (name == "sequential") return Placement::kSequential;
  if (name == "interleaved") return Placement::kInterleaved;
  if (name == "back_and_forth") return Placement::kBackAndForth;
  throw Error("unknown placement '" + name + "': sequential, interleaved or back_and_forth");
}

void set_positions(TestPlan& plan, std::size_t n, Placement placement) {
  std::vector<std::size_t> order;
  order.reserve(n);
  std::vector<int> sweep;
  switch (placement) {
    case Placement::kSequential:
      for (std::size_t k = 0; k < n; ++k) order.push_back(k);
      break;
    case Placement::kInterleaved: {
      // Bit-reversed counting over the next power of two, keeping the indices below n.
      unsigned bits = 0;
      while ((std::size_t{1} << bits) < n) ++bits;
      for (std::size_t k = 0; k < (std::size_t{1} << bits); ++k) {
        std::size_t r = 0;
        for (unsigned b = 0; b < bits; ++b) r |= ((k >> b) & 1u) << (bits - 1 - b);
        if (r < n) order.push_back(r);
      }
      break;
    }
    case Placement::kBackAndForth:
      for (std::size_t k = 0; k < n; k += 2) {
        order.push_back(k);
        sweep.push_back(+1);
      }
      for (std::size_t k = (n % 2 == 0 ? n - 1 : n - 2); k < n; k -= 2) {
        order.push_back(k);
        sweep.push_back(-1);
        if (k < 2) break;
      }
      break;
  }
  plan.positions.clear();
  for (std::size_t k : order) {
    plan.positions.push_back(2.0 * units::kPi * static_cast<double>(k) / static_cast<double>(n));
  }
  plan.sweep = std::move(sweep);
}

}  // namespace poise::procedures
