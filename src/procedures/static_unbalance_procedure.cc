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
  long rhs_calls = 0;
};

namespace {
using Context = StaticUnbalanceWorkspace::Context;
constexpr int kStates = 7;  // phi, phidot, y, ydot, z, zdot, integral of the angle error

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

// Amplifier current: PID plus acceleration feed-forward, clamped at the limit.
inline double drive_current(const Context& c, const Reference& r, const double* y, bool* saturated) {
  const double cmd = (c.kp * (r.phi - y[0]) + c.kd * (r.rate - y[1]) + c.ki * y[6] + c.j_ff * r.acc) /
                     c.kt_nominal;
  const double i = std::clamp(cmd, -c.i_max, c.i_max);
  if (saturated) *saturated = i != cmd;
  return i;
}

int rhs(double t, const double* y, double* ydot, void* user) {
  auto* c = static_cast<Context*>(user);
  ++c->rhs_calls;
  bool sat = false;
  const Reference r = reference(*c, t);
  const double i = drive_current(*c, r, y, &sat);
  const models::DiskState s{y[0], y[1], y[2], y[3], y[4], y[5]};
  const auto acc = models::disk_accelerations(c->disk, c->gravity, s, c->kt_true * i + c->disturbance_torque);
  ydot[0] = y[1];
  ydot[1] = acc[0];
  ydot[2] = y[3];
  ydot[3] = acc[1];
  ydot[4] = y[5];
  ydot[5] = acc[2];
  // Conditional integration: the integrator holds while the amplifier saturates.
  ydot[6] = sat ? 0.0 : r.phi - y[0];
  for (int k = 0; k < kStates; ++k) {
    if (!std::isfinite(ydot[k])) return 1;  // recoverable: CVODE retries a smaller step
  }
  return 0;
}

}  // namespace

StaticUnbalanceWorkspace::StaticUnbalanceWorkspace(const solvers::CvodeOptions& opt)
    : ctx_(new Context), integrator_(new solvers::CvodeIntegrator(kStates, rhs, ctx_, opt)) {}

StaticUnbalanceWorkspace::~StaticUnbalanceWorkspace() {
  delete integrator_;
  delete ctx_;
}

MeasurementResult run_static_unbalance_procedure(const TestPlan& plan, const GimbalTruth& truth,
                                            sampling::RandomStream& noise,
                                            StaticUnbalanceWorkspace& ws, int record_position,
                                            std::vector<RecordSample>* record) {
  require(plan.positions.size() >= 4, "the static-unbalance test needs at least 4 positions");
  require(plan.oscillation.period > 0 && plan.oscillation.periods >= 1,
          "the oscillation needs a positive period and at least one whole period");
  require(plan.acquisition.rate_hz > 0, "acquisition rate must be positive");
  require(plan.sweep.empty() || plan.sweep.size() == plan.positions.size(),
          "the sweep directions must be given for every position or for none");
  Context& c = ws.context();
  solvers::CvodeIntegrator& integ = ws.integrator();
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
  const auto n_samples = static_cast<long>(std::llround(osc.periods * osc.period * acq.rate_hz));
  require(n_samples >= 2, "fewer than 2 current samples in the integration window");
  const double dt = (t2 - t1) / static_cast<double>(n_samples);

  MeasurementResult out;
  out.positions.reserve(plan.positions.size());
  double offset = acq.offset;
  std::array<double, kStates> y{};
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
    pr.theta_true = theta_nominal + truth.turntable_zero + plan.positioning_error * normal.next();
    offset += acq.offset_drift * normal.next();
    const double window_offset = offset + acq.offset_noise * normal.next();
    c.gravity = models::gravity_in_gimbal(plan.gravity, pr.theta_true, truth.axis_tilt,
                                          truth.axis_tilt_azimuth);
    c.disturbance_torque = dist.harmonic2_torque * std::sin(2.0 * pr.theta_true + dist.harmonic2_phase) +
                           dist.direction_torque * pr.sweep +
                           (static_cast<int>(ip) == dist.bump_position ? dist.bump_torque : 0.0);
    // Locked at the start angle, supports deflected statically, servo integrator empty.
    const auto defl = models::static_deflection(c.disk, c.gravity);
    const double y0[kStates] = {osc.centre - c.amplitude, 0.0, defl[0], 0.0, defl[1], 0.0, 0.0};
    integ.reset(0.0, y0);
    integ.advance(c.t0, c.t0, false);  // settle (stop at the reference's corner)
    integ.advance(t1, t1, false);      // lead-in: the start transient is not integrated
    double sum_i = 0.0, sum_track2 = 0.0;
    long k = 0;
    double t = integ.time(), tn = 0.0;
    std::array<double, 6 * kStates> poly{};
    int q = integ.step_polynomial(poly, &tn);
    while (k < n_samples) {
      const double tk = t1 + static_cast<double>(k) * dt;
      if (tk > t) {
        t = integ.advance(t2, t2, true);
        q = integ.step_polynomial(poly, &tn);
        continue;
      }
      // The current only needs phi, phidot and the error integral (states 0, 1, 6).
      const double h = tk - tn;
      for (int i : {0, 1, 6}) {
        double v = poly[static_cast<std::size_t>(q * kStates + i)];
        for (int j = q - 1; j >= 0; --j) v = v * h + poly[static_cast<std::size_t>(j * kStates + i)];
        y[static_cast<std::size_t>(i)] = v;
      }
      bool sat = false;
      const Reference ref = reference(c, tk);
      const double i_true = drive_current(c, ref, y.data(), &sat);
      pr.saturated = pr.saturated || sat;
      // Sensor: offset and white noise, then the ADC's range and resolution.
      const double drift = dist.offset_drift_rate * (t_start + tk);
      double i_meas = i_true + window_offset + drift + (acq.noise_rms > 0 ? acq.noise_rms * normal.next() : 0.0);
      i_meas = std::clamp(std::round(i_meas / lsb) * lsb, -acq.adc_full_scale, acq.adc_full_scale);
      sum_i += i_meas;
      if (record && static_cast<int>(ip) == record_position) record->push_back({tk - t1, i_meas, y[0]});
      const double e = ref.phi - y[0];
      sum_track2 += e * e;
      pr.max_abs_phi = std::max(pr.max_abs_phi, std::abs(y[0] - c.centre));
      ++k;
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
