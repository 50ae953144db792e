#pragma once
// Test data Poise did not make: an independent generator of static-unbalance turntable tables
// and raw one-position records. It shares no code with src/ (not the procedures, not the
// models, not the estimators): its own gimbal equation, its own servo, its own RK4, its own
// acquisition and its own turntable plans, so the diagnosis is tested against a simulator
// whose assumptions are not its own.
//
// Gimbal at one locked turntable position theta (gimbal angle phi about its axis, small):
//   J phi'' = K_T(t) i - B phi' - C tanh(phi'/w_e) - D tanh(phi'/w_e)_+ - U sin(theta + b + phi)
//             - S sin(2 (theta + phi) + b2) - k_c phi - T_c sin(N phi + psi) - M_dir(sweep) - M_0
// (U = m g e the unbalance torque; S an anisotropic-sag 2nd harmonic; D an extra friction in
// the + direction; T_c cogging of order N; M_dir a cable hysteresis offset that depends on the
// direction the turntable came from; M_0 a constant). tanh(x)_+ = max(tanh x, 0).
// Servo: phi_ref = (A T / 2 pi)(1 - cos(2 pi t / T)), i = [J a_ref + K_v (w_ref - phi') +
// K_p (phi_ref - phi) + K_i int (phi_ref - phi)] / K_T0: a PID position loop with inertia
// feed-forward; the integral supplies the static torque. RK4, fixed step.
// The test's torque per position: K_T0 times the mean measured current over whole periods
// after one settling period (Eq. 21 of Yang 2015, done here independently).
// Acquisition: measured current = true current + sensor offset(t) + white noise, quantised by a
// 16-bit ADC over +-range; the encoder angle quantised to 21 bits per turn.
// Table noise: a per-position torque disturbance (air flow, cable creep, turntable settling),
// white or AR(1) in time order, added to the position's torque; the loop integral passes a
// constant disturbance to the mean current exactly, so it is added after integration.
#include <cstdint>
#include <string>
#include <vector>

namespace poise::testdata {

struct Plant {
  double inertia = 2.0e-3;     // J, kg m^2
  double viscous = 2.0e-3;     // B, N m s/rad
  double coulomb = 0.4e-3;     // C, N m
  double coulomb_plus = 0.0;   // D, N m (asymmetry)
  double unbalance = 12.91e-3; // U, N m
  double phase_rad = 45.5 * 3.14159265358979323846 / 180.0;  // b
  double sag_h2 = 0.0;         // S, N m
  double sag_h2_phase = 0.5;   // b2, rad
  double cable_k = 0.0;        // k_c, N m/rad
  double cogging = 0.0;        // T_c, N m
  int cogging_order = 0;       // N
  double cogging_phase = 0.3;  // psi, rad
  double constant = 3.4e-3;    // M_0, N m
  double direction_offset = 0.0;  // M_dir = +-this, N m, sign of the approach direction
  double higher_harmonic = 0.0;   // an effect outside the candidate list: sin(k_h theta), N m
  int higher_order = 9;
};

struct Servo {
  double kt0 = 0.05;         // nominal torque constant, N m/A
  double amplitude = 0.139;  // A, rad/s (swing +-1.27 deg at T = 1 s)
  double period = 1.0;       // T, s
  double bandwidth_hz = 20.0;
  double dt = 2.5e-4;        // RK4 step, s
  int periods = 2;           // integrated periods after one settling period
};

// Slow effects of the test, as functions of absolute time.
struct TimeEffects {
  double step = 0.0, step_time = -1.0;      // sensor offset jump, N m-equivalent, at s
  double settle = 0.0, settle_tau = 300.0;  // exponential offset settle(0) e^(-t/tau), N m
  double kt_rate = 0.0;                     // K_T(t) = K_T0 (1 + rate t), 1/s
  double drift = 0.0;                       // linear sensor drift, N m/s
};

struct Acquisition {
  double current_noise = 2e-3;  // A rms per sample
  double adc_range = 2.0;       // +-A, 16 bits
  int adc_bits = 16;
  int encoder_bits = 21;
  double sample_rate = 1000.0;  // Hz
  double offset_drift = 0.0;    // current-sensor offset drift, A/s (records only)
};

// One turntable position of a plan.
struct Visit {
  double theta_deg = 0.0;
  int sweep = 1;        // direction the turntable came from
  double time_s = 0.0;  // start of the position
};

// Plans: one-direction sweep 0..350 step 10; forward then back over the same 36 angles;
// cable-limited split sweep 0..180 then 0..-170; a shuffled order of 36 angles.
std::vector<Visit> forward_sweep(int n = 36, double seconds_per_position = 60.0);
std::vector<Visit> forward_and_back(double seconds_per_position = 60.0);
std::vector<Visit> split_sweep(double seconds_per_position = 60.0);
std::vector<Visit> shuffled(std::uint64_t seed, double seconds_per_position = 60.0);

// Noise-free torque per visit (N m) from integrating the plant and servo: K_T0 mean(i_meas).
std::vector<double> position_torques(const Plant& p, const Servo& s, const TimeEffects& e,
                                     const std::vector<Visit>& plan);

struct TableNoise {
  double sigma = 0.2e-3;  // N m, innovation sd
  double rho = 0.0;       // AR(1) in time order
};

// A torque table (theta_deg, torque_mNm, time_s, sweep) as a CSV text, and the same columns.
struct Table {
  std::vector<double> theta_deg, torque_mNm, time_s;
  std::vector<int> sweep;
};
Table make_table(const std::vector<Visit>& plan, const std::vector<double>& torque_Nm,
                 const TableNoise& noise, std::uint64_t seed);

// A raw record of one position: time_s, current_A (ADC counts times LSB), phi (rad, encoder
// counts times LSB), over settle + periods; the record starts after the settling period.
struct Record {
  std::vector<double> t, current, phi;
};
Record make_record(const Plant& p, const Servo& s, const Acquisition& a, double theta_deg,
                   std::uint64_t seed);

}  // namespace poise::testdata
