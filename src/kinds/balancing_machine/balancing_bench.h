#pragma once
/// Internal to the balancing-machine kind: one sample's draws and bench (the machine as built,
/// its measuring runs, placements and estimators) and the experiments a study runs on it, each
/// writing its outputs in the order the kind declares them (balancing_study_setup.cc).
#include <complex>
#include <initializer_list>
#include <vector>

#include "engine/study_files/study_config.h"
#include "kinds/balancing_machine/balancing_iso_tests.h"
#include "kinds/balancing_machine/balancing_model.h"
#include "kinds/balancing_machine/balancing_sections.h"
#include "kinds/balancing_machine/balancing_slots.h"
#include "procedures/balancing_measurement.h"
#include "sampling/random_stream.h"

namespace poise::kinds::balancing_machine {
using engine::StudyConfig;
namespace detail {

// Draws of one sample: unit-scope values from the design point, test-scope ones from the
// sample's stream each time they are asked for (in a fixed order: deterministic).
class Draws {
 public:
  Draws(const BalancingModel& m, sampling::RandomStream& rs) : m_(m), rs_(rs) {}
  /// The sample's stream of test-scope draws (also the accuracy test's random angles).
  sampling::RandomStream& stream() { return rs_; }
  double value[kSlotCount]{};
  double angle[kSlotCount]{};
  bool unit[kSlotCount]{};
  /// The value for this use: the unit draw, or a fresh test-scope draw.
  double use(Slot s) {
    if (unit[s]) return value[s];
    const engine::ToleranceSpec& t = (m_.*kSlots[s].tol).spec;
    return kSlots[s].magnitude ? t.dist.magnitude_quantile(rs_.uniform()) : t.dist.quantile(rs_.uniform());
  }

 private:
  const BalancingModel& m_;
  sampling::RandomStream& rs_;
};

using cd = std::complex<double>;
using models::PlaneMass;

struct Bench {
  Bench(const BalancingModel& m, const StudyConfig& c, Draws& d, sampling::RandomStream& n,
        procedures::BalancingWorkspace& w)
      : model(m), cfg(c), draws(d), noise(n), ws(w), sensors(m.sensors) {}
  const BalancingModel& model;
  const StudyConfig& cfg;
  Draws& draws;
  sampling::RandomStream& noise;
  procedures::BalancingWorkspace& ws;
  models::SpringPlateMachineParams machine_r;      // as built, rotor R
  models::SpringPlateMachineParams machine_piece;  // as built, the test piece
  models::SpringPlateMachineParams nominal;        // design values (closed form)
  procedures::SensorConfig sensors;
  procedures::CorrectionPlanes planes;
  double omega_nominal = 0.0;
  long steps = 0, rhs = 0;
  procedures::InfluenceCalibration cal;
  bool calibrated = false;

  /// A mass placed in a testing hole (with the hole's and the mass's errors).
  PlaneMass place(double mass, double radius, double angle, double height) {
    const double dm = draws.use(kTestMass), dr = draws.use(kHoleRadius), da = draws.use(kHoleAngle);
    return {mass * (1.0 + dm), radius + dr, angle + da, height};
  }
  /// A correction mass cancelling the estimated plane unbalance u (kg m) at radius r.
  PlaneMass correction(cd u, double radius, double height) {
    const double dm = draws.use(kCorrMass), da = draws.use(kCorrAngle);
    return {std::abs(u) / radius * (1.0 + dm), radius, std::arg(-u) + da, height};
  }
  /// One run; amplitudes referred to the nominal speed when the machine compensates.
  Eigen::Vector2cd measure(const models::SpringPlateMachineParams& machine, const std::vector<PlaneMass>& masses) {
    procedures::BalancingRunConfig run = model.run;
    run.speed_rpm *= 1.0 + draws.use(kSpeed);
    const procedures::BalancingMeasurement m =
        procedures::run_balancing_measurement(machine, masses, 0.0, run, sensors, noise, ws);
    steps += m.solver.steps;
    rhs += m.solver.rhs_evals;
    Eigen::Vector2cd a = m.amplitudes;
    if (model.speed_compensation) a *= (omega_nominal / m.omega) * (omega_nominal / m.omega);
    return a;
  }
  /// Plane unbalances (kg m) by the influence coefficients.
  Eigen::Vector2cd influence(const Eigen::Vector2cd& a) { return procedures::influence_estimate(cal, a); }
  /// Plane unbalances (kg m) by the corrected closed form on the design values.
  Eigen::Vector2cd closed_form(const Eigen::Vector2cd& a) {
    return procedures::closed_form_estimate(nominal, a, omega_nominal, 0.0, planes).planes;
  }
  Eigen::Vector2cd reading(const Eigen::Vector2cd& a) {
    return balancing_sections(cfg).estimator == "influence" ? influence(a) : closed_form(a);
  }
};

/// Rotor R on the machine: its residual unbalance as plane masses (radius 1 m) and as complex
/// plane unbalances, and the two correction planes' heights.
struct RotorR {
  std::vector<PlaneMass> masses;
  cd residual[2];
  double z1 = 0.0, z2 = 0.0;
};

IsoBench iso_bench(Bench& bench, double z1, double z2);
std::vector<PlaneMass> with(std::vector<PlaneMass> base, std::initializer_list<PlaneMass> extra);
cd unbalance_of(const PlaneMass& m);
double rel_error(cd estimate, cd truth);

/// separation: the sensors' response to a test mass in each surface's holes; its spread and the sensor-2 line against
/// height.
void separation_test(Bench& bench, const BalancingExperiment& x, const RotorR& r, std::vector<double>& out,
                     std::size_t& o);
/// umar: the indicated unbalance of a test mass stepped round each plane (minimum achievable residual unbalance).
void umar_test(Bench& bench, const BalancingExperiment& x, const RotorR& r, std::vector<double>& out, std::size_t& o);
/// stability: readings of a test mass stepped round one surface, optionally after balancing first.
void stability_test(Bench& bench, const BalancingExperiment& x, const RotorR& r, std::vector<double>& out,
                    std::size_t& o);
/// urr: unbalance reduction ratio, one correction run and the ISO 21940-21 indication of known test masses.
void urr_test(Bench& bench, const BalancingExperiment& x, const RotorR& r, std::vector<double>& out, std::size_t& o);
/// umar_iso: the ISO 21940-21 two-plane minimum achievable residual unbalance.
void umar_iso_test(Bench& bench, const BalancingExperiment& x, const RotorR& r, std::vector<double>& out,
                   std::size_t& o);
/// accuracy: a test piece with plane unbalances at random angles, by influence coefficients and closed form; couple
/// interference and the plates' motion.
void accuracy_test(Bench& bench, const BalancingExperiment& x, const RotorR& r, std::vector<double>& out,
                   std::size_t& o);

/// calibration: the machine's influence coefficients from its calibration on rotor R (|C| in N per kg m, phase in
/// deg), sensor by sensor, plane by plane.
void calibration_outputs(const Bench& bench, std::vector<double>& out, std::size_t& o);

}  // namespace detail
}  // namespace poise::kinds::balancing_machine
