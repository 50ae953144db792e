#pragma once
/// The LOS study of a two-axis seeker: Monte Carlo of the exact kinematic chain over the
/// field of regard, beside the paper's analytic budget recomputed from the same inputs.
///
/// Per sample i: design point u(i) -> error realization (SeekerSampler) -> pointing error
/// at every (yaw, pitch) of the grid (LosGrid) -> per-sample outputs:
///   los_max_arcsec     greatest total pointing error over the field of regard
///   los_rms_arcsec     RMS of the total error over the grid
///   yaw_max_arcsec     greatest |yaw-angle error|
///   pitch_max_arcsec   greatest |pitch-angle error|
///   los_max_px         los_max in pixels (model's IFOV)
///   field_ok_fraction  fraction of grid points meeting the requirement
///   yaw_max_px, pitch_max_px   the yaw and pitch figures in pixels
/// A sample that fails (non-finite result, exception) is kept with its reason.
#include <cstddef>
#include <functional>
#include <map>

#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/kind_interface/output_spec.h"
#include "engine/kind_interface/procedure_study.h"
#include "engine/results/wide_columns.h"
#include "engine/study_files/study_config.h"
#include "model_files/seeker_model.h"
#include "models/seeker_los_budget.h"
#include "models/seeker_los_chain.h"
#include "sampling/design.h"
#include "sampling/statistics.h"

namespace poise::kinds::seeker_los {
using engine::InputSpec;
using engine::McResult;
using engine::OutputDeclaration;
using engine::OutputSpec;
using engine::ProcedureStudy;
using engine::RunControl;
using engine::SampleResult;
using engine::SampleSink;
using engine::StudyConfig;
using engine::WideColumnsSpec;
using model_files::SeekerModel;
using model_files::SeekerSampler;

/// Names and units of the per-sample outputs, in order.
inline constexpr OutputDeclaration kSeekerOutputs[] = {
    {"los_max_arcsec", "arcsec", "greatest total LOS error over the field of regard"},
    {"los_rms_arcsec", "arcsec", "RMS total LOS error over the field of regard"},
    {"yaw_max_arcsec", "arcsec", "greatest |yaw-angle error| over the field"},
    {"pitch_max_arcsec", "arcsec", "greatest |pitch-angle error| over the field"},
    {"los_max_px", "px", "greatest total LOS error in pixels"},
    {"field_ok_fraction", "1", "fraction of the field of regard meeting the requirement"},
    {"yaw_max_px", "px", "greatest |yaw-angle error| in pixels"},
    {"pitch_max_px", "px", "greatest |pitch-angle error| in pixels"},
};
inline constexpr std::size_t kNumSeekerOutputs = std::size(kSeekerOutputs);

/// A study ready to run: model, sampler, design and grid built and validated. The engine runs
/// it as every kind (engine/run/procedure_runner.h), on its sample loop; each sample's grid
/// values (SampleResult::field) go to the field sink, which writes samples.h5 and makes the
/// field figures from them (seeker_field.h).
class SeekerLosStudy final : public ProcedureStudy {
 public:
  SeekerLosStudy(StudyConfig config, SeekerModel model, std::size_t samples, std::uint64_t seed);

  const StudyConfig& config() const override { return config_; }
  const SeekerModel& model() const { return model_; }
  const SeekerSampler& sampler() const { return sampler_; }
  const models::LosGrid& grid() const { return grid_; }
  double requirement_rad() const { return requirement_rad_; }
  std::size_t samples() const { return samples_; }
  std::uint64_t seed() const { return seed_; }

  const std::vector<InputSpec>& inputs() const override { return inputs_; }
  const std::vector<std::string>& input_names() const override { return input_names_; }
  const std::vector<OutputSpec>& outputs() const override { return outputs_; }
  const std::vector<std::string>& output_names() const override { return output_names_; }
  std::string model_name() const override { return model_.name; }
  std::string model_source() const override { return model_.source; }
  std::vector<std::string> design_dimension_names() const override { return input_names_; }
  std::vector<std::string> design_dimension_tolerances() const override { return sampler_.column_tolerances(); }
  /// The model's tolerances, each set to zero in turn for contributions.
  std::vector<std::string> tolerance_keys() const override { return model_.tolerance_keys(); }

  struct Workspace {
    std::vector<double> u;
    models::LosGrid::Workspace grid;
    std::vector<models::PointingError> errors;
  };
  Workspace make_workspace() const;
  /// Computes sample i alone (replay); depends only on (seed, samples, method, i). The
  /// result's field is the total error at each grid point (arcsec).
  void compute(std::size_t i, Workspace& ws, SampleResult& out) const;
  /// The per-sample outputs (kSeekerOutputs order, into `outputs`) of one error realization
  /// and, unless `grid_total_arcsec` is empty, the total error at each grid point. Throws
  /// poise::Error for a non-finite pointing error.
  void evaluate_state(const models::SeekerErrorState& state, Workspace& ws, std::span<double> outputs,
                      std::span<float> grid_total_arcsec) const;
  /// The grid values' layout in samples.h5: one column per grid point, its yaw and pitch.
  WideColumnsSpec field_spec() const;
  /// Per-grid-point errors of sample i (for replay reports).
  std::vector<models::PointingError> grid_errors(std::size_t i) const;

  /// Runs samples [done.size(), n) on the engine's sample loop (run_procedure_samples), the
  /// grid values of each going to its field sink (seeker_field.h); a resumed run's `done`
  /// samples are not computed again: their grid values come from the interrupted run's
  /// samples.h5.
  McResult run(int threads, bool progress, const SampleSink& sink, std::span<const SampleResult> done,
               const RunControl& control = {}) const override;
  SampleResult replay(std::size_t i) const override;

  /// summary.json "details": the LOS limit, the grid, the tolerances sampled, the pooled field
  /// figures and the shares of units and of the field meeting the limit.
  nlohmann::json details(const McResult& mc) const override;
  /// The report's own sections: units and field within the limit, the field figures in arcsec
  /// and pixels, the map of p95 over the field, the tolerances sampled.
  void report_sections(const McResult& mc, const std::string& plots_dir, bool plots, std::vector<std::string>& figures,
                       std::ostringstream& html) const override;

 private:
  StudyConfig config_;
  SeekerModel model_;
  SeekerSampler sampler_;
  std::size_t samples_;
  std::uint64_t seed_;
  sampling::Design design_;
  models::LosGrid grid_;
  double requirement_rad_;
  std::vector<InputSpec> inputs_;
  std::vector<std::string> input_names_, output_names_;
  std::vector<OutputSpec> outputs_;
};

}  // namespace poise::kinds::seeker_los
