#pragma once
/// The balancing-machine study (Wang & Wang 2014, ISO 21940-21 tests): Monte Carlo over the
/// machine's tolerances, each sample one machine as built running the study's experiments
/// end to end (every run: CVODE from rest through the start transient, sensors with gain
/// error and noise, synchronous demodulation; then the estimator the machine displays).
///
/// Per sample:
///   * the machine as built: each of the three plates' thickness, width and length drawn
///     separately, E, lever, sensor 1's height, sensor gains, the standard rotor's residual
///     unbalance in the two correction planes (at random angles);
///   * calibration by influence coefficients on rotor R with the calibration mass in each
///     correction plane (as production machines do); the closed form uses the machine's
///     design lever, the nominal speed and the design end condition's split, as the paper does
///     (of the plates' stiffnesses it needs none: each sensor reads its own plate as built,
///     sensor 1 one of the two horizontal plates, so only their difference reaches it);
///   * every run draws its own speed deviation and placement errors (scope "test").
/// Outputs (names start with the experiment's name; units from the suffix):
///   omega1_Hz, omega2_Hz, hard_bearing_ratio         the machine as built with rotor R
///   static_buckling_ratio, static_stress_MPa (largest plate stress under the weight),
///   static_tilt_urad, weight_stiffness_loss_pct, pendulum_margin_ratio   the machine as built
///       under the weight of frame and rotor R (machine_statics in balancing_model.h)
///   separation: NAME_s<k>_sensor1_mN, NAME_s<k>_sensor2_mN  effect of the test mass on
///       surface k (|A - A_bare|, mean over the holes), NAME_sensor1_spread_pct (max - min over
///       the surfaces, of the mean), NAME_sensor2_zero_height_mm (height where the fitted line of
///       sensor 2 against height crosses 0: the torsion centre), NAME_sensor2_linearity_pct
///   umar: NAME_plane<p>_kgm = (X_max - X_min) r / 2 of plane p, NAME_kgm (Eq. 18: their sum),
///       NAME_xmax<p>_g, NAME_xmin<p>_g, NAME_p<p>_k<k>_g the readings, NAME_true_residual<p>_kgm
///       (the rotor's residual, what U_mar estimates), NAME_max_reading_error_g
///   stability: NAME_residual_gmm (largest plane residual after balancing first),
///       NAME_plane<p>_max_dev_pct, NAME_p<p>_k<k>_ratio (reading / mean), NAME_pass_ratio (1/0)
///   umar_iso (balancing_iso_tests.h): both planes loaded at once, moved through the positions:
///       NAME_plane<p>_kgm ((X_max - X_min) r / 2), NAME_plane<p>_max_dev_g (largest |X - mean|),
///       NAME_plane<p>_mean_g, NAME_pass_ratio (every reading within mean +- claim / r),
///       NAME_p<p>_k<k>_g the readings
///   stability: the experiment's `variant` says whether it is the test as Wang 2014 prints it
///       ("wang2014") or a set-up of Poise's own ("poise"); the report heads it so
///   urr: NAME_plane<p>_pct, NAME_min_pct, NAME_pass_ratio: Poise's figure, 1 - |after| / |before|
///       after one physical correction (true unbalances; the correction masses' placement
///       errors included); NAME_iso_plane<p>_pct, NAME_iso_min_pct, NAME_iso_pass_ratio: ISO
///       21940-21's, the indication of the known test masses against their values (no correction)
///   accuracy: NAME_u_error_{ic,cf}_gmm = |U^ - U| (g mm), NAME_v_error_{ic,cf}_gmm =
///       |V^ - V| / (z2 - z1) (the couple error as equal and opposite unbalances in the two
///       planes, g mm), NAME_plane_error_{ic,cf}_pct (|U_p^ - U_p| / |U_p|, the larger of the
///       two planes), NAME_interference_{ic,cf}_per_mm (static unbalance
///       indicated per unit of a pure couple unbalance, ISO 21940-21's I_s,c),
///       NAME_x_amplitude_um (amplitude of the horizontal plates' motion for a static
///       unbalance of piece_unbalance)
///   ic: influence coefficients; cf: the corrected closed form (Eq. 13).
#include <memory>
#include <string>
#include <vector>

#include "engine/kind_interface/procedure_study.h"
#include "kinds/balancing_machine/balancing_model.h"
#include "sampling/design.h"

namespace poise::sampling {
class RandomStream;
}

namespace poise::kinds::balancing_machine {
using engine::McResult;
using engine::ProcedureStudyBase;
using engine::SampleResult;
using engine::StudyConfig;
using engine::ValidationError;
namespace detail {
class Draws;  // one sample's draws (balancing_study.cc)
}

class BalancingStudy : public ProcedureStudyBase<BalancingStudy> {
 public:
  /// Throws ValidationError if the study does not fit the model (surfaces, paper keys, scopes).
  BalancingStudy(StudyConfig config, BalancingModel model, std::size_t samples, std::uint64_t seed);

  const StudyConfig& config() const override { return config_; }
  std::size_t samples() const { return samples_; }
  /// Per-test draws (kProcedure) and the sensors' noise (kNoise): two streams, two Sobol groups.
  std::vector<std::string> randomness_sources() const override { return {"per-test draws", "measurement noise"}; }
  std::size_t design_dimension() const { return design_.dimension(); }
  /// Per-test draws and measurement noise beyond the design point.
  bool has_own_randomness() const override { return true; }
  bool has_solver() const override { return true; }
  /// Every toleranced slot of the model, the per-test ones included (for contributions).
  std::vector<std::string> tolerance_keys() const override;
  std::string model_name() const override { return model_.name; }
  std::string model_source() const override { return model_.source; }
  const BalancingModel& model() const { return model_; }

  /// At given inputs (poise.Study.evaluate): the unit-scope tolerances' columns; the per-test
  /// draws and the noise of point k are those of sample k.
  bool evaluates_inputs() const override { return true; }
  std::vector<double> nominal_inputs() const override;
  void evaluate_point(std::size_t k, std::span<const double> inputs, std::span<double> outputs) const override;

  using Workspace = procedures::BalancingWorkspace;
  std::unique_ptr<Workspace> make_workspace() const;
  void compute(std::size_t i, Workspace& ws, SampleResult& out) const;
  nlohmann::json solver_json(const McResult& mc) const override;
  /// The nominal machine: stiffnesses, masses, natural frequencies, hard-bearing check.
  nlohmann::json details(const McResult& mc) const override;
  void report_sections(const McResult& mc, const std::string& plots_dir, bool plots, std::vector<std::string>& figures,
                       std::ostringstream& html) const override;

  /// Runs per sample (for the progress estimate and the validate summary).
  std::size_t runs_per_sample() const;

  /// Inconsistent rotor inputs, each a message naming file and key: a rotor denser than lead
  /// (11,340 kg/m^3), a test or calibration radius outside the rotor. Warnings, not errors:
  /// the run goes on, the CLI prints them and summary.json lists them (details.warnings).
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  StudyConfig config_;
  BalancingModel model_;
  std::size_t samples_;
  std::uint64_t seed_;
  std::vector<std::string> warnings_;
  std::vector<std::string> input_warnings() const;
  std::size_t dimension_ = 0;
  sampling::Design design_;
  /// Every test of the study on the machine as built from `d` (its unit draws set, its
  /// per-test ones drawn as used), the sensors' noise from `noise`: the outputs, solver
  /// counters and any failure into `out`.
  void run_tests(detail::Draws& d, sampling::RandomStream& noise, Workspace& ws, SampleResult& out) const;
};

}  // namespace poise::kinds::balancing_machine
