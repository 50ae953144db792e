#pragma once
/// Measurement procedure of the vertical hard-bearing balancing machine on spring plates
/// (Wang & Wang 2014; model in models/spring_plate_machine.h), simulated end to end:
///
///   1. The rotor is brought to speed n (it spins at constant speed from t = 0, shaft angle
///      phi = omega t, as spring_plate_rhs takes it) and the machine starts from rest; CVODE
///      integrates the 2-DOF equations through the start transient.
///   2. Settling: the start transient is a free vibration that decays at best as
///      exp(-sigma t), sigma the slowest decay rate of the damped machine (the smallest
///      -Re(lambda) of the 4x4 state matrix; about zeta omega_1). The run waits
///      settle_time_constants (default 20, exp(-20) = 2e-9) time constants tau = 1 / sigma,
///      rounded up to whole revolutions (at least min_settle_revolutions).
///   3. Acquisition: sensor 1 (force in horizontal plate 1, F_n1 = k5,1 x: its own plate's
///      as-built stiffness, the model's sensor_forces) and sensor 2 (force in the torsional
///      plate, F_n2 = force_factor k6 l theta, by its end condition) are
///      sampled, triggered by the shaft encoder, with a whole number of samples per revolution
///      (round(sample_rate / n)) over N whole revolutions; each sensor has a relative gain
///      error and white noise.
///   4. Synchronous demodulation against the rotation reference: a = (2/K) sum s cos(phi_k),
///      b = (2/K) sum s sin(phi_k), A = a - i b, so that s ~ Re(A e^{i phi}) with the same
///      convention as the model's complex amplitudes (q = Re(X e^{i omega t})). Over whole
///      revolutions with K >= 3 samples per revolution, DC and all harmonics 2..K/r-1 cancel
///      exactly (discrete orthogonality).
///
/// Estimators:
///   (a) the corrected hard-bearing closed form (Eq. 13 corrected, unbalance_from_sensor_forces):
///       U e^{i a3} = 2 F_n1 / w^2, V e^{i a4} = (F_n2 l - 2 F_n1 h) / w^2, then the two
///       correction-plane unbalances U1 + U2 = U, U1 (z1 - h) + U2 (z2 - h) = V. It needs the
///       machine's k5, k6, l, ideal sensors, and omega << omega_1.
///   (b) influence coefficients, as production machines are calibrated: bare rotor (A0), a
///       known test mass on plane 1 (A1), then on plane 2 (A2); column j of the influence
///       matrix C is (A_j - A0) / T_j; a rotor's plane unbalances are C^{-1} A. Exact for a
///       linear machine at any speed and independent of the sensors' gains (they scale the
///       rows of C and of A alike).
#include <complex>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "models/spring_plate_machine.h"
#include "sampling/random_stream.h"
#include "solvers/cvode_integrator.h"

namespace poise::procedures {

struct SensorConfig {
  double gain_error_1 = 0.0;       ///< relative: measured = (1 + g) true, sensor 1
  double gain_error_2 = 0.0;       ///< sensor 2
  double noise_rms = 0.0;          ///< white noise per sample, each sensor (N)
  double sample_rate_hz = 2000.0;  ///< nominal; rounded to whole samples per revolution
  /// Height a (m) of sensor 1's measuring point above the torsion shaft axis. 0 (as
  /// designed): it reads the horizontal plates, F_n1 = k5 x. Otherwise it reads the
  /// horizontal motion of the swinging part at that height, F_n1 = k5 (x + a theta): the
  /// couple unbalance then leaks into sensor 1 (what fixing the vibration centre avoids).
  double sensor_1_offset = 0.0;
};

/// How the sensor signals of a run are made.
///   kIntegrated   CVODE integrates the machine from rest through the start transient and the
///                 acquisition (steps 1-3 above): the full model.
///   kSteadyState  the fast model: the exact steady state q = Re(X e^{i w t}) of the same linear
///                 equations, (K - w^2 M_q + i w C) X = f^ (models::steady_state_response),
///                 sampled at the same instants with the same gains and the same noise draws
///                 in the same order. It leaves out what the settling leaves of the start
///                 transient (below exp(-settle_time_constants) of it) and the solver's error;
///                 nothing else differs (tests/procedures/balancing_measurement_test.cc compares both).
enum class BalancingResponse { kIntegrated, kSteadyState };

struct BalancingRunConfig {
  BalancingResponse response = BalancingResponse::kIntegrated;
  double speed_rpm = 80.0;              ///< n (r/min); Wang 2014's test speed n_1
  int revolutions = 8;                  ///< N whole revolutions demodulated (>= 2)
  double settle_time_constants = 20.0;  ///< settle this many slowest decay time constants
  int min_settle_revolutions = 2;
  /// CVODE options. The states are integrated scaled by the size of the expected response
  /// (positions by |X| of the exact steady state, velocities by omega_2 |X|), so atol is
  /// relative to that size; atol_per_state, if given, applies to the scaled states too.
  solvers::CvodeOptions solver{1e-10, 1e-10, {}, 0.0, 10000000, 0};
};

struct BalancingMeasurement {
  Eigen::Vector2cd amplitudes;       ///< demodulated sensor amplitudes (F_n1, F_n2) (N)
  double omega = 0.0;                ///< rad/s
  double decay_time_constant = 0.0;  ///< tau = 1 / sigma (s)
  double settle_time = 0.0;          ///< s, whole revolutions
  int settle_revolutions = 0;
  int samples_per_revolution = 0;
  /// Settling check: |A(last rev) - A(previous rev)| per sensor, relative to |A| (measured
  /// signal, so it contains the noise floor ~ noise_rms sqrt(2 / K) / |A| when noise is on).
  Eigen::Vector2d last_revolution_change = Eigen::Vector2d::Zero();
  solvers::CvodeStats solver;  ///< counters of this run
};

/// Reference-synchronous demodulation: A = (2/K) sum s_k e^{-i phi_k} (= a - i b). Exact for
/// a sinusoid Re(A e^{i phi}) sampled uniformly over whole revolutions (K >= 3 per revolution).
std::complex<double> demodulate(std::span<const double> samples, std::span<const double> shaft_angles);

/// Slowest decay rate sigma = min -Re(lambda) of the damped machine (1/s). Throws poise::Error
/// if the machine is undamped (no steady state is ever reached).
double slowest_decay_rate(const models::SpringPlateMachineParams& p);

/// One CVODE integrator and its right-hand side data per worker thread, reused across runs.
class BalancingWorkspace {
 public:
  explicit BalancingWorkspace(const solvers::CvodeOptions& opt = BalancingRunConfig{}.solver);
  ~BalancingWorkspace();
  BalancingWorkspace(const BalancingWorkspace&) = delete;
  BalancingWorkspace& operator=(const BalancingWorkspace&) = delete;
  struct Context;  // defined in the .cc
  Context& context() { return *ctx_; }
  solvers::CvodeIntegrator& integrator() { return *integrator_; }

 private:
  std::unique_ptr<Context> ctx_;  // complete in the .cc, where the constructor and destructor are
  std::unique_ptr<solvers::CvodeIntegrator> integrator_;
};

/// One measurement run (steps 1-4 above). `noise` is advanced only if noise_rms > 0.
/// Throws poise::Error on bad input or a solver failure.
BalancingMeasurement run_balancing_measurement(const models::SpringPlateMachineParams& machine,
                                               const models::SpringPlateUnbalance& unbalance,
                                               const BalancingRunConfig& run, const SensorConfig& sensors,
                                               sampling::RandomStream& noise, BalancingWorkspace& ws);

/// The same for masses on planes (Eqs. 1-2, couple about `reference_height`).
BalancingMeasurement run_balancing_measurement(const models::SpringPlateMachineParams& machine,
                                               std::span<const models::PlaneMass> masses, double reference_height,
                                               const BalancingRunConfig& run, const SensorConfig& sensors,
                                               sampling::RandomStream& noise, BalancingWorkspace& ws);

// ---- estimators -----------------------------------------------------------------------------

/// Heights z (m) of the two correction planes above the torsion shaft axis.
struct CorrectionPlanes {
  double height_1 = 0.0;
  double height_2 = 0.0;
};

/// Split U (kg m) and V (kg m^2, about height h) into the two planes' unbalances (kg m):
/// U1 + U2 = U, U1 (z1 - h) + U2 (z2 - h) = V. Throws if z1 == z2.
Eigen::Vector2cd split_to_planes(std::complex<double> u, std::complex<double> v, double height,
                                 const CorrectionPlanes& planes);

struct ClosedFormEstimate {
  std::complex<double> static_unbalance;  ///< U e^{i a3} (kg m)
  std::complex<double> couple_unbalance;  ///< V e^{i a4} (kg m^2), about `height`
  double height = 0.0;
  models::SpringPlateUnbalance machine;  ///< the same as magnitudes and phases
  Eigen::Vector2cd planes;               ///< U1, U2 (kg m); correction masses go opposite
};

/// Eq. 13 corrected on demodulated amplitudes, then split to the planes.
ClosedFormEstimate closed_form_estimate(const models::SpringPlateMachineParams& machine,
                                        const Eigen::Vector2cd& amplitudes, double omega, double height,
                                        const CorrectionPlanes& planes);

struct InfluenceCalibration {
  Eigen::Matrix2cd coefficients;  ///< C: A = C (U1, U2) (N per kg m), column j = plane j
  Eigen::Vector2cd bare_amplitudes;
  Eigen::Vector2cd bare_unbalance;  ///< C^{-1} A0: the calibration rotor's own plane unbalances
};

/// C from the three runs; test_j = m r e^{i a} of the test mass on plane j (kg m).
/// Throws if a test mass is zero or C is singular (planes too close / too small an effect).
InfluenceCalibration calibrate_influence(const Eigen::Vector2cd& bare, const Eigen::Vector2cd& with_test_1,
                                         std::complex<double> test_1, const Eigen::Vector2cd& with_test_2,
                                         std::complex<double> test_2);

/// Plane unbalances (U1, U2) (kg m) of a rotor from its amplitudes: C^{-1} A.
Eigen::Vector2cd influence_estimate(const InfluenceCalibration& cal, const Eigen::Vector2cd& amplitudes);

struct UnbalanceEstimates {
  ClosedFormEstimate closed_form;
  Eigen::Vector2cd influence;  ///< (U1, U2) by influence coefficients (kg m)
  InfluenceCalibration calibration;
  BalancingMeasurement measurement;                    ///< the unknown rotor's run
  std::vector<BalancingMeasurement> calibration_runs;  ///< bare, test 1, test 2
};

/// The whole procedure: calibrate with `calibration_rotor` (masses, any planes) and the test
/// masses `test_1`, `test_2` (their heights define the correction planes), then measure
/// `rotor` and estimate its plane unbalances both ways. Unbalances are taken about
/// `reference_height` (any value; the closed form uses the same h).
UnbalanceEstimates estimate_unbalance(const models::SpringPlateMachineParams& machine,
                                      std::span<const models::PlaneMass> calibration_rotor,
                                      const models::PlaneMass& test_1, const models::PlaneMass& test_2,
                                      std::span<const models::PlaneMass> rotor, double reference_height,
                                      const BalancingRunConfig& run, const SensorConfig& sensors,
                                      sampling::RandomStream& noise, BalancingWorkspace& ws);

}  // namespace poise::procedures
