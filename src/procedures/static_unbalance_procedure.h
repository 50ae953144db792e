#pragma once
/// The static-unbalance test of Yang et al. 2015 (Sec. 5.1), simulated end to end:
/// for each turntable position theta_i the gimbal is locked, settles, is driven by its
/// servo in a small sinusoidal oscillation phidot = A sin(2 pi t / T), and the sampled
/// drive current is averaged over N whole periods (Eq. 21: M_i = K_T mean(i_a)); then
/// M(theta) = MT_s sin(theta + b) + MK is fitted by least squares (Eq. 22) and the
/// counterweight m = MT_s / (R g) placed opposite the unbalance (Eq. 23).
///
/// Instruments modelled: torque motor (true K_T against the nominal K_T the estimate
/// uses, current limit), PID servo with acceleration feed-forward tracking
/// phi_ref = phi_c - (A T / 2 pi) cos(2 pi t / T), bearing friction (viscous and Coulomb)
/// and cable torque (in the disk model), current acquisition (rate, white noise, offset
/// with a per-position random-walk drift, ADC resolution and range), turntable positioning
/// error, gimbal axis tilted against the turntable axis, bearing run-out.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "estimators/sine_fit.h"
#include "models/disk_rotor.h"
#include "sampling/random_stream.h"
#include "solvers/cvode_integrator.h"

namespace poise::procedures {

struct ServoConfig {
  double bandwidth_hz = 20.0;  ///< position loop crossover
  double damping = 0.8;
  double integral_ratio = 0.1;    ///< Ki = Kp * w_c * ratio
  double inertia_estimate = 0.0;  ///< J used for the gains and the feed-forward (kg m^2)
  double current_limit = 1.0;     ///< amplifier limit (A)
  double kt_nominal = 0.1;        ///< K_T the controller and the estimate assume (N m/A)
};

struct OscillationConfig {
  double rate_amplitude = 0.0;               ///< A (rad/s)
  double period = 4.0;                       ///< T (s)
  int periods = 2;                           ///< N whole periods integrated
  double lead_in = 0.5;                      ///< time after the oscillation starts before the integration
                                             ///< window (s); the window still spans N whole periods
  double settle_time = 1.0;                  ///< holding at the start angle after locking (s)
  double centre = 0.0;                       ///< phi_c (rad)
  double swing_range = 0.05235987755982988;  ///< the test's stated range of |phi| (rad; Yang 2015: 3 deg)
};

struct AcquisitionConfig {
  double rate_hz = 1000.0;
  double noise_rms = 0.0;     ///< white current noise (A)
  double offset = 0.0;        ///< current-sensor offset at the first position (A)
  double offset_drift = 0.0;  ///< random-walk step of the offset per position (A, 1 sigma)
  double offset_noise = 0.0;  ///< the sensor's low-frequency (1/f) noise as it averages over
                              ///< one position's window: white from position to position (A)
  int adc_bits = 16;
  double adc_full_scale = 2.0;  ///< +- range (A)
};

/// How the rotor's supports enter the simulation (model key [rotor] supports).
enum class Supports {
  kDynamic,      ///< the full 7-state model: phi and the support deflections y, z with their
                 ///< mass, stiffness and damping (models/disk_rotor.h)
  kQuasiStatic,  ///< y'' = z'' = 0: the supports follow their static load, phi obeys
                 ///< (J + m e^2) phi'' = Q_phi (models::rigid_axis_acceleration)
};

/// How a position's mean current is found (the gimbal kind's fast model is kPeriodMean).
///   kIntegrated  CVODE integrates the servo and the rotor through the settle, the lead-in and
///                the window (the full model).
///   kPeriodMean  the rotor follows the reference exactly, phi = phi_c - a cos(w t'); over
///                whole periods the mean of (J + m e^2) phi'' is zero, so the rigid rotor's
///                equation (J + m e^2) phi'' = K_T i + T_d + Q_phi(phi, phidot) gives the mean
///                current  mean(i) = -(mean(Q_phi) + T_d) / K_T, the mean taken by the
///                trapezoidal rule over one period of the reference (exact to rounding for
///                the trigonometric terms with enough points: 64, or more for a cogging order
///                N, 2 N a + 32). It leaves out the tracking error, the start transient's
///                remainder after the lead-in and the supports' dynamics; the acquisition's
///                errors are drawn as on the integrated path (the same draws). A position
///                that would saturate the drive, must be sampled (ADC coarser than the noise,
///                near full scale) or whose record is kept is integrated as in kIntegrated.
///                rms_tracking is 0 and max_abs_phi the reference's swing a on the other
///                positions. Compared with the full model in tests/procedures/static_unbalance_procedure_test.cc.
enum class PositionModel { kIntegrated, kPeriodMean };

struct TestPlan {
  std::vector<double> positions;   ///< nominal turntable angles theta_i (rad), in test order
  std::vector<int> sweep;          ///< approach direction per position (+1/-1); empty = all +1
  double move_time = 5.0;          ///< turntable move and lock between positions (s)
  double positioning_error = 0.0;  ///< turntable error per position (rad, 1 sigma)
  ServoConfig servo;
  OscillationConfig oscillation;
  AcquisitionConfig acquisition;
  solvers::CvodeOptions solver;
  double gravity = 9.80665;
  Supports supports = Supports::kDynamic;
  PositionModel position_model = PositionModel::kIntegrated;
};

/// Effects a real rig may have that the test's model (Eqs. 21-22) does not declare; all
/// off by default. They let the residual diagnosis be tested on data whose effect is known.
struct Disturbances {
  double offset_drift_rate = 0.0;  ///< current-sensor offset drifting linearly in time (A/s)
  double harmonic2_torque = 0.0;   ///< torque T2 sin(2 theta + psi2) at each position (N m):
  double harmonic2_phase = 0.0;    ///< an out-of-round bearing under the gravity load
  double direction_torque = 0.0;   ///< torque +-T_d by approach direction (cable wind-up, N m)
  int bump_position = -1;          ///< one position disturbed by a bump (index, -1 = none)
  double bump_torque = 0.0;        ///< its extra torque during that position (N m)
};

/// The unit under test as it really is (one Monte Carlo sample).
struct GimbalTruth {
  models::DiskRotorParams disk;  ///< eccentricity = |unbalance + run-out| / m
  double kt_true = 0.1;          ///< real K_T (N m/A)
  double axis_tilt = 0.0;        ///< gimbal axis vs turntable axis (rad)
  double axis_tilt_azimuth = 0.0;
  double turntable_zero = 0.0;  ///< registration error of the turntable zero (rad)
  Disturbances disturbances;
};

struct PositionResult {
  double theta_nominal = 0.0;  ///< rad
  double time = 0.0;           ///< middle of the integration window since the test began (s)
  int sweep = 1;               ///< approach direction
  double theta_true = 0.0;     ///< rad
  double torque = 0.0;         ///< M_i (N m), Eq. 21
  double max_abs_phi = 0.0;    ///< largest |phi - phi_c| in the integration window (rad),
                               ///< the swing about the commanded centre (the +-3 deg limit)
  double rms_tracking = 0.0;   ///< RMS of phi_ref - phi in the window (rad)
  bool saturated = false;      ///< current limit reached in the window
};

/// One sample of a raw record: what the acquisition saw at one position.
struct RecordSample {
  double t;        ///< s since the start of the integration window
  double current;  ///< measured drive current (A), with noise and ADC
  double phi;      ///< gimbal angle from the encoder (rad)
};

struct MeasurementResult {
  std::vector<PositionResult> positions;
  estimators::SineFitResult fit;  ///< MT_s (N m), b (rad), MK (N m)
  solvers::CvodeStats solver;     ///< counters of this measurement
  double rhs_seconds = 0.0;       ///< time inside the right-hand side (if timed)
};

/// Per-thread state: the integrators (one per support formulation, made on first use) and
/// buffers, reused for every position and sample.
class StaticUnbalanceWorkspace {
 public:
  explicit StaticUnbalanceWorkspace(solvers::CvodeOptions opt);
  struct Context;  // what the right-hand side reads (defined in the .cc)
  ~StaticUnbalanceWorkspace();
  StaticUnbalanceWorkspace(const StaticUnbalanceWorkspace&) = delete;
  StaticUnbalanceWorkspace& operator=(const StaticUnbalanceWorkspace&) = delete;
  Context& context() { return *ctx_; }
  solvers::CvodeIntegrator& integrator(Supports supports);

 private:
  solvers::CvodeOptions opt_;
  std::unique_ptr<Context> ctx_;  // complete in the .cc, where the constructor and destructor are
  // Made on first use; destroyed before the context they point into (declared after it).
  std::unique_ptr<solvers::CvodeIntegrator> dynamic_, quasi_static_;
};

/// Runs the whole test on `truth`; noise comes from `noise` (advanced). Throws
/// poise::Error on a solver failure (the caller records the sample as failed).
/// `record_position` >= 0 keeps the raw samples of that position in `record`.
///
/// Eq. 21's mean current: the drive current is integrated as a state over the window,
/// Q_i = int_{t1}^{t2} i dt, beside int (phi_ref - phi)^2 dt (the RMS tracking) and the
/// clipped excess int max(|i_cmd| - i_max, 0) dt (> 0: `saturated`); |phi - phi_c| is
/// taken at every step end and at the turning points inside a step (phidot = 0, from the
/// step's interpolant). The acquisition's own errors are then drawn in distribution:
/// the mean of n samples of white noise sigma through an ADC of step q (q <= sigma, so the
/// rounding is a uniform dither) is one normal draw of variance (sigma^2 + q^2/12) / n; the
/// offset drift's mean is its value at the samples' mean time. A position whose raw record
/// is kept, or whose ADC steps are coarser than the noise, or whose current could reach the
/// ADC's full scale (i_max + offsets + 6 sigma), is sampled as the instrument does (n
/// samples from the interpolant, each with its noise, rounded and clipped), with its
/// per-sample noise from a sub-stream keyed by a word drawn from `noise`: the main stream
/// advances the same way on both paths, so any position can be replayed with its record.
MeasurementResult run_static_unbalance_procedure(const TestPlan& plan, const GimbalTruth& truth,
                                                 sampling::RandomStream& noise, StaticUnbalanceWorkspace& ws,
                                                 int record_position = -1, std::vector<RecordSample>* record = nullptr);

/// Order in which the turntable visits n positions evenly spaced over 360 deg.
enum class Placement {
  kSequential,    ///< 0, 360/n, 2 * 360/n, ... deg
  kInterleaved,   ///< van der Corput (bit-reversed) order: 0, 180, 90, 270, ... deg, so that a
                  ///< drift in time is not a function of the angle
  kBackAndForth,  ///< even positions going up, odd ones coming back down (approach -1): a
                  ///< linear drift then adds the same to both legs' sum at every angle
};
Placement parse_placement(const std::string& name);  ///< "sequential" | "interleaved" | "back_and_forth"

/// Sets plan.positions (rad, in test order) and plan.sweep for n positions.
void set_positions(TestPlan& plan, std::size_t n, Placement placement);

/// Duration of one position (s): move and lock, settle, lead-in, N whole periods.
inline double position_duration(const TestPlan& plan) {
  const OscillationConfig& o = plan.oscillation;
  return plan.move_time + ((o.settle_time + o.lead_in) + o.periods * o.period);
}

/// Duration of the whole test (s): every position of the plan, one after the other.
inline double test_duration(const TestPlan& plan) {
  return static_cast<double>(plan.positions.size()) * position_duration(plan);
}

/// Eq. 23: counterweight mass for amplitude MT_s at radius R.
inline double counterweight_mass(double amplitude, double radius, double g) { return amplitude / (radius * g); }

}  // namespace poise::procedures
