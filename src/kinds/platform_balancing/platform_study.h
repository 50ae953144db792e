#pragma once
/// The balancing campaign of a three-gimbal platform (Yang 2015 Sec. 2: test order inner ->
/// middle -> outer) simulated over the platform's centroid tolerances and the test's own:
/// per sample, one platform as built, and for each test order of the study
///   1. each axis in turn measured with the complete simulated single-axis test
///      (procedures::run_static_unbalance_procedure: turntable positions, servo-driven
///      oscillation, CVODE, sampled current, Eq. 21, Eq. 22 fit) on the assembly that turns
///      about it, the other gimbals locked with their locking errors (mapping in
///      platform_model.h);
///   2. its Eq. 23 counterweight placed with its tolerances in the gimbal's correction plane
///      (the later tests and the residual see it);
///   3. the residual: the axis torque of the exact statics (platform_statics.h) on a grid of
///      the three gimbal angles, under gravity and under gravity plus the stated carrier
///      acceleration (max and RMS over the grid), and the residual first moment
///      perpendicular to each axis at the lock angles;
///   4. the LOS error: every axis' residual torque under the carrier profile (a manoeuvre
///      and vibration lines) through its stabilization loop (stabilization_loop.h) gives
///      its angle error; the LOS error is |dw x d| (platform_statics.h) at each grid point
///      and time; per sample its peak and RMS over the profile at the worst grid point
///      (temporal statistics of one unit), the ensemble being the samples.
/// The same platform and the same test tolerances (drawn per axis test) and noise streams
/// (per axis) serve every order: common random numbers, so differences between orders are
/// the order's.
///
/// Outputs: initial_<axis>_torque_max_mNm (before balancing, gravity, max over the grid);
/// per order label L ("imo" = inner, middle, outer) and axis:
///   L_<axis>_measured_mNm       MT_s of that axis' test
///   L_<axis>_residual_gmm       |S perpendicular to the axis| after the campaign, lock angles
///   L_<axis>_residual_grid_max_gmm   the same, greatest over the gimbal-angle grid (the carried
///                               gimbals turn their first moments; the lock angles are one point)
///   L_<axis>_torque_max_mNm     max |axis torque| over the grid, gravity
///   L_<axis>_torque_rms_mNm     RMS over the grid, gravity
///   L_<axis>_torque_max_acc_mNm, L_<axis>_torque_rms_acc_mNm   gravity + stated acceleration
///   L_los_max_arcsec, L_los_rms_arcsec   peak and RMS over the profile, worst grid point
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "engine/kind_interface/procedure_study.h"
#include "engine/study_files/study_config.h"
#include "kinds/platform_balancing/platform_model.h"
#include "sampling/design.h"
#include "sampling/random_stream.h"

namespace poise::kinds::platform_balancing {
using engine::McResult;
using engine::ProcedureStudyBase;
using engine::SampleResult;
using engine::StudyConfig;

/// Draws of one sample: per tolerance, up to 6 instances (centroid x, y, z; per axis test or
/// motor by models::Axis; lock errors 2 per test: the two locked gimbals in axis order).
struct PlatformDraws {
  enum Slot {
    kInnerCentroid,
    kMiddleCentroid,
    kOuterCentroid,
    kKtCalibration,
    kKtDrift,
    kLockError,
    kFixtureTilt,
    kTurntableZero,
    kGimbalZero,
    kCounterweightMass,
    kCounterweightRadius,
    kCounterweightAngle,
    kCounterweightPlane,
    kNumSlots
  };
  std::array<std::array<double, 6>, kNumSlots> value{};
  std::array<double, 3> tilt_azimuth{};  ///< rad, per axis test
};

/// One axis test of a campaign.
struct AxisTestRecord {
  double true_unbalance = 0.0;      ///< |S perpendicular| of the assembly when tested (kg m)
  double measured = 0.0;            ///< MT_s (N m)
  double phase = 0.0;               ///< b (rad)
  double counterweight_mass = 0.0;  ///< kg, as placed
  double max_swing = 0.0;           ///< rad
  bool saturated = false;
};

struct CampaignResult {
  models::Platform platform;            ///< after the campaign, counterweights included
  std::array<AxisTestRecord, 3> tests;  ///< by models::Axis
  long solver_steps = 0, rhs_evals = 0;
};

class PlatformStudy : public ProcedureStudyBase<PlatformStudy> {
 public:
  /// `shafting_los_arcsec`: the per-unit shafting LOS error of the seeker study (empty = none).
  PlatformStudy(StudyConfig config, PlatformModel model, std::size_t samples, std::uint64_t seed,
                std::vector<double> shafting_los_arcsec = {}, double pixel_arcsec = 0.0);

  /// Per-test draws (kProcedure) and each axis's measurement noise: two sources, two Sobol groups.
  std::vector<std::string> randomness_sources() const override { return {"per-test draws", "measurement noise"}; }
  std::size_t design_dimension() const { return design_.dimension(); }
  /// Per-test draws and measurement noise beyond the design point.
  bool has_own_randomness() const override { return true; }
  bool has_solver() const override { return true; }
  /// Every toleranced slot of the model, the per-test ones included (for contributions).
  std::vector<std::string> tolerance_keys() const override;
  const StudyConfig& config() const override { return config_; }
  std::size_t samples() const { return samples_; }
  std::string model_name() const override { return model_.name; }
  std::string model_source() const override { return model_.source; }
  const PlatformModel& model() const { return model_; }

  using Workspace = procedures::StaticUnbalanceWorkspace;
  std::unique_ptr<Workspace> make_workspace() const;
  void compute(std::size_t i, Workspace& ws, SampleResult& out) const;
  nlohmann::json solver_json(const McResult& mc) const override;
  nlohmann::json details(const McResult& mc) const override;
  void report_sections(const McResult& mc, const std::string& plots_dir, bool plots, std::vector<std::string>& figures,
                       std::ostringstream& html) const override;

  /// The unit-scope draws of sample i and its test-scope ones (from its stream).
  PlatformDraws draws(std::size_t i) const;
  /// The platform as built for these draws (centroid offsets, no counterweights).
  models::Platform as_built(const PlatformDraws& d) const;
  /// One campaign in `order` (axis indices). Noise from (seed, axis, i). Throws on a solver failure.
  CampaignResult run_campaign(std::size_t i, const models::Platform& built, const PlatformDraws& d,
                              const std::array<int, 3>& order, Workspace& ws) const;

  struct Residual {
    std::array<double, 3> perpendicular{}, max_g{}, rms_g{}, max_acc{}, rms_acc{};  ///< kg m, N m
    std::array<double, 3> perpendicular_grid_max{};  ///< kg m, greatest over the angle grid
    double los_max = 0.0, los_rms = 0.0;             ///< rad
  };
  /// Residual torques over the grid and the LOS error under the profile.
  Residual residual(const models::Platform& p) const;
  /// Nominal assembly inertia about each axis at the lock angles (test servo, LOS loop).
  const std::array<double, 3>& axis_inertia() const { return axis_inertia_; }

 private:
  StudyConfig config_;
  PlatformModel model_;
  std::size_t samples_;
  std::uint64_t seed_;
  std::vector<double> shafting_, shafting_sorted_;
  double pixel_arcsec_ = 0.0;
  std::vector<std::pair<int, int>> unit_slots_;  ///< (slot, instance) drawn from the design
  std::size_t dimension_ = 0;
  sampling::Design design_;
  std::vector<models::GimbalAngles> grid_;
  std::array<double, 3> axis_inertia_{};
  std::array<models::StabilizationLoop, 3> loops_;
  std::array<std::array<std::vector<double>, 3>, 3> loop_response_;  ///< [axis][component](t): h_k * a_j
  std::vector<double> profile_time_;
  /// details(): each gimbal with its loop, and the combined LOS budget lines (platform_report.cc).
  nlohmann::json gimbals_json() const;
  nlohmann::json los_budget_json(const McResult& mc) const;
};

}  // namespace poise::kinds::platform_balancing
