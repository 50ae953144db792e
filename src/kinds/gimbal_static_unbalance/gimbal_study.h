#pragma once
/// The gimbal static-unbalance study: Monte Carlo over the rig's tolerances of whole test
/// campaigns (groups of loads x repeats, each a complete simulated measurement: turntable
/// positions, servo-driven oscillation, current acquisition, Eq. 21, fit Eq. 22,
/// counterweight Eq. 23 placed with its tolerances).
///
/// Per sample (one campaign on one as-built rig) and per group g, the outputs are
///   g_rmse_torque_mNm, g_rmse_angle_deg     RMSE of MT_s and b against the loads (the
///                                           paper's Eqs. 25-28)
///   g_mean_torque_error_mNm, g_mean_angle_error_deg, g_sd_torque_mNm, g_sd_angle_deg
///   g_mean_offset_mNm                       mean fitted MK
///   g_max_residual_gmm                      largest residual unbalance after the
///                                           counterweight, about the bearing axis with the
///                                           run-out's m r (counterweight_residual.h)
///   g_max_swing_deg                         largest |phi - phi_c| reached (the +-3 deg check)
///   g_mean_fit_rmse_mNm                     RMS residual of the Eq. 22 fit (Table 1: 0.23)
///   g_test_time_min                         duration of one test of the group (min): per
///                                           position, move and lock, settle, lead-in and
///                                           the N periods integrated
/// A position whose drive saturates, or whose swing leaves [oscillation] swing_range, fails
/// its sample with the reason; summary.json "details" gives the saturated share.
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/kind_interface/procedure_study.h"
#include "engine/study_files/study_config.h"
#include "model_files/gimbal_model.h"
#include "sampling/design.h"
#include "sampling/statistics.h"

namespace poise::kinds::gimbal_static_unbalance {
using engine::McResult;
using engine::ProcedureStudyBase;
using engine::SampleResult;
using engine::StudyConfig;
using engine::UserPartsSampler;
using model_files::DiskSampler;
using model_files::GimbalModel;

class GimbalStudy : public ProcedureStudyBase<GimbalStudy> {
 public:
  GimbalStudy(StudyConfig config, GimbalModel model, std::size_t samples, std::uint64_t seed);

  std::size_t design_dimension() const { return design_.dimension(); }
  /// Per-test draws and measurement noise beyond the design point.
  bool has_own_randomness() const override { return true; }
  bool has_solver() const override { return true; }
  /// Every toleranced slot of the model, the per-test ones (K_T drift, zeros) included.
  std::vector<std::string> tolerance_keys() const override;
  const StudyConfig& config() const override { return config_; }
  std::size_t samples() const { return samples_; }
  std::string model_name() const override { return model_.name; }
  std::string model_source() const override { return model_.source; }
  const GimbalModel& model() const { return model_; }

  /// The rig as built for one sample: its unit-scope draws and the disk's effects (defined
  /// in gimbal_study.cc).
  struct RigAsBuilt;
  /// At given inputs (poise.Study.evaluate): the unit-scope tolerances' columns; the per-test
  /// draws and the noise of point k are those of sample k. A rig whose disk or parts are drawn
  /// ([geometry]) has derived columns and is not evaluated at inputs.
  bool evaluates_inputs() const override { return !disk_ && !parts_; }
  std::vector<double> nominal_inputs() const override;
  void evaluate_point(std::size_t k, std::span<const double> inputs, std::span<double> outputs) const override;

  using Workspace = procedures::StaticUnbalanceWorkspace;
  std::unique_ptr<Workspace> make_workspace() const;
  /// Sample i alone (replayable): depends only on (seed, samples, method, i).
  void compute(std::size_t i, Workspace& ws, SampleResult& out) const;
  /// The groups' paper_rmse_torque and paper_rmse_angle.
  nlohmann::json solver_json(const McResult& mc) const override;
  /// summary.json "details": the saturated share and the out-of-range share of the samples
  /// (with 95% Wilson intervals), the error mechanism, the counterweight placement and the
  /// plausibility warnings of the model.
  nlohmann::json details(const McResult& mc) const override;
  void report_sections(const McResult& mc, const std::string& plots_dir, bool plots, std::vector<std::string>& figures,
                       std::ostringstream& html) const override;

 private:
  StudyConfig config_;
  GimbalModel model_;
  std::size_t samples_;
  std::uint64_t seed_;
  std::size_t dimension_ = 0;
  std::optional<DiskSampler> disk_;        ///< the disk as built ([geometry]), after the tolerances' dimensions
  std::optional<UserPartsSampler> parts_;  ///< or the rotor's parts as built ([[geometry.part]])
  /// Fails the sample (throws poise::Error, "drive saturated: ..." or "swing out of range: ...")
  /// when a position of test `test` saturated its drive or swung past [oscillation] swing_range.
  void check_positions(const procedures::MeasurementResult& m, const std::string& group, std::size_t test,
                       double load_torque, double load_angle) const;
  /// Every group's tests on `rig`, the per-test draws and noise from stream `stream`: the
  /// outputs and solver counters into `out` (throws poise::Error for a failed position).
  void run_campaign(std::uint64_t stream, const RigAsBuilt& rig, Workspace& ws, SampleResult& out) const;
  std::size_t geometry_dimension() const { return disk_ ? disk_->dimension() : parts_ ? parts_->dimension() : 0; }
  sampling::Design design_;
};

}  // namespace poise::kinds::gimbal_static_unbalance
