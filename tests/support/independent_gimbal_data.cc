#include "independent_gimbal_data.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>

namespace poise::testdata {
namespace {

constexpr double kPi = 3.14159265358979323846;

double positive_tanh(double x) { return std::max(std::tanh(x), 0.0); }

double quantise(double v, double lsb) { return lsb * std::round(v / lsb); }

// Integrates one position for (1 + periods) periods; calls sample(t_local, i_true, phi) at the
// acquisition rate during the integrated periods. State: phi, phi', int(phi_ref - phi).
template <class Sample>
void integrate_position(const Plant& p, const Servo& s, const TimeEffects& e, double theta,
                        int sweep, double t0, double sample_rate, Sample sample) {
  const double wn = 2.0 * kPi * s.bandwidth_hz;
  const double kp = p.inertia * wn * wn * 3.0, kv = p.inertia * wn * 3.0,
               ki = p.inertia * wn * wn * wn;
  const double w = 2.0 * kPi / s.period, amp = s.amplitude / w;
  const double we = 1e-3;  // rad/s: friction smoothing
  const auto current = [&](double t, const std::array<double, 3>& x) {
    const double ref = amp * (1.0 - std::cos(w * t)), wref = s.amplitude * std::sin(w * t);
    const double aref = s.amplitude * w * std::cos(w * t);
    return (p.inertia * aref + kv * (wref - x[1]) + kp * (ref - x[0]) + ki * x[2]) / s.kt0;
  };
  const auto rhs = [&](double t, const std::array<double, 3>& x) {
    const double i = current(t, x);
    const double kt = s.kt0 * (1.0 + e.kt_rate * (t0 + t));
    const double v = x[1];
    const double load = p.viscous * v + p.coulomb * std::tanh(v / we) +
                        p.coulomb_plus * positive_tanh(v / we) +
                        p.unbalance * std::sin(theta + p.phase_rad + x[0]) +
                        p.sag_h2 * std::sin(2.0 * (theta + x[0]) + p.sag_h2_phase) +
                        p.cable_k * x[0] +
                        p.cogging * std::sin(p.cogging_order * x[0] + p.cogging_phase) +
                        p.direction_offset * sweep + p.constant +
                        p.higher_harmonic * std::sin(p.higher_order * theta);
    const double ref = amp * (1.0 - std::cos(w * t));
    return std::array<double, 3>{v, (kt * i - load) / p.inertia, ref - x[0]};
  };
  // Start at rest with the integral holding the static torque roughly (the loop settles
  // within the first period either way).
  std::array<double, 3> x{0.0, 0.0, 0.0};
  const int steps_per_period = static_cast<int>(std::lround(s.period / s.dt));
  const int total = steps_per_period * (1 + s.periods);
  const int every = std::max(1, static_cast<int>(std::lround(1.0 / (sample_rate * s.dt))));
  for (int k = 0; k < total; ++k) {
    const double t = k * s.dt;
    if (k >= steps_per_period && (k - steps_per_period) % every == 0) {
      sample(t, current(t, x), x[0]);
    }
    const auto k1 = rhs(t, x);
    std::array<double, 3> y;
    for (int j = 0; j < 3; ++j) y[j] = x[j] + 0.5 * s.dt * k1[j];
    const auto k2 = rhs(t + 0.5 * s.dt, y);
    for (int j = 0; j < 3; ++j) y[j] = x[j] + 0.5 * s.dt * k2[j];
    const auto k3 = rhs(t + 0.5 * s.dt, y);
    for (int j = 0; j < 3; ++j) y[j] = x[j] + s.dt * k3[j];
    const auto k4 = rhs(t + s.dt, y);
    for (int j = 0; j < 3; ++j) x[j] += s.dt / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
  }
}

double sensor_offset(const TimeEffects& e, double t) {
  double o = e.drift * t + e.settle * std::exp(-t / e.settle_tau);
  if (e.step_time >= 0.0 && t >= e.step_time) o += e.step;
  return o;  // N m-equivalent
}

std::vector<Visit> with_times(const std::vector<double>& angles, double seconds) {
  std::vector<Visit> v;
  for (std::size_t k = 0; k < angles.size(); ++k) {
    const int dir = k == 0 ? 1 : (angles[k] >= angles[k - 1] ? 1 : -1);
    v.push_back({angles[k], dir, seconds * static_cast<double>(k)});
  }
  return v;
}

}  // namespace

std::vector<Visit> forward_sweep(int n, double seconds) {
  std::vector<double> a;
  for (int k = 0; k < n; ++k) a.push_back(360.0 / n * k);
  return with_times(a, seconds);
}

std::vector<Visit> forward_and_back(double seconds) {
  std::vector<double> a;
  for (int k = 0; k < 36; ++k) a.push_back(10.0 * k);
  for (int k = 35; k >= 0; --k) a.push_back(10.0 * k);
  std::vector<Visit> v = with_times(a, seconds);
  v[36].sweep = -1;  // the turntable turns back at 350 deg
  return v;
}

std::vector<Visit> split_sweep(double seconds) {
  std::vector<double> a;
  for (int k = 0; k <= 18; ++k) a.push_back(10.0 * k);
  for (int k = 0; k <= 17; ++k) a.push_back(-10.0 * k);
  std::vector<Visit> v = with_times(a, seconds);
  for (std::size_t k = 19; k < v.size(); ++k) v[k].sweep = -1;  // unwound through 0, then down
  return v;
}

std::vector<Visit> shuffled(std::uint64_t seed, double seconds) {
  std::vector<double> a;
  for (int k = 0; k < 36; ++k) a.push_back(10.0 * k);
  std::mt19937_64 rng(seed);
  std::shuffle(a.begin(), a.end(), rng);
  return with_times(a, seconds);
}

std::vector<double> position_torques(const Plant& p, const Servo& s, const TimeEffects& e,
                                     const std::vector<Visit>& plan) {
  const double lsb = 2.0 * 2.0 / std::pow(2.0, 16);  // 16-bit ADC over +-2 A
  std::vector<double> out;
  for (const Visit& v : plan) {
    double sum = 0.0;
    int count = 0;
    integrate_position(p, s, e, v.theta_deg * kPi / 180.0, v.sweep, v.time_s, 1000.0,
                       [&](double t, double i, double) {
                         const double meas = i + sensor_offset(e, v.time_s + t) / s.kt0;
                         sum += quantise(meas, lsb);
                         ++count;
                       });
    out.push_back(s.kt0 * sum / count);
  }
  return out;
}

Table make_table(const std::vector<Visit>& plan, const std::vector<double>& torque,
                 const TableNoise& noise, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, noise.sigma);
  Table t;
  double e = 0.0;
  for (std::size_t k = 0; k < plan.size(); ++k) {  // plan is in time order
    const double u = g(rng);
    e = k == 0 ? u / std::sqrt(1.0 - noise.rho * noise.rho) : noise.rho * e + u;
    t.theta_deg.push_back(plan[k].theta_deg);
    t.torque_mNm.push_back((torque[k] + e) * 1e3);
    t.time_s.push_back(plan[k].time_s);
    t.sweep.push_back(plan[k].sweep);
  }
  return t;
}

Record make_record(const Plant& p, const Servo& s, const Acquisition& a, double theta_deg,
                   std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, a.current_noise);
  const double lsb_i = 2.0 * a.adc_range / std::pow(2.0, a.adc_bits);
  const double lsb_phi = 2.0 * kPi / std::pow(2.0, a.encoder_bits);
  Record r;
  integrate_position(p, s, TimeEffects{}, theta_deg * kPi / 180.0, 1, 0.0, a.sample_rate,
                     [&](double t, double i, double phi) {
                       r.t.push_back(t);
                       r.current.push_back(quantise(i + g(rng) + a.offset_drift * t, lsb_i));
                       r.phi.push_back(quantise(phi, lsb_phi));
                     });
  return r;
}

}  // namespace poise::testdata
