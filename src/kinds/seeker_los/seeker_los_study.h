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

#include "models/seeker_los_budget.h"
#include "models/seeker_los_chain.h"
#include "sampling/design.h"
#include "sampling/statistics.h"
#include "model_files/seeker_model.h"
#include "engine/output_spec.h"
#include "engine/study_config.h"
#include "engine/wide_columns.h"

namespace poise::studies {

struct SeekerSampleResult {
  std::size_t index = 0;
  bool ok = true;
  std::string message;
  std::vector<double> inputs;  ///< display units, SeekerSampler::columns()
  std::vector<double> outputs; ///< kOutputNames order
  std::vector<float> grid_total_arcsec;  ///< total error at each grid point
};

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

/// Aggregated results of one Monte Carlo run.
struct SeekerMcResult {
  std::size_t n = 0, failures = 0;
  std::vector<std::pair<std::size_t, std::string>> failed;  ///< (index, reason), first 100
  std::vector<sampling::Summary> outputs;                    ///< per kSeekerOutputs
  sampling::Summary pooled;      ///< total error over (sample, grid point), arcsec
  sampling::Estimate fraction_samples_ok;  ///< samples whose whole field meets the requirement
  sampling::Estimate fraction_field_ok;    ///< mean field_ok_fraction (t interval)
  std::vector<double> map_p50, map_p95, map_p99_73;  ///< per grid point, arcsec (with field statistics)
  nlohmann::json field_file;               ///< the grid values' file (WideColumnsWriter::close), rank 0
  std::vector<double> los_max_sorted;      ///< for histogram/CDF
  double wall_seconds = 0.0;
  std::vector<std::vector<double>> values;  ///< per output, ok samples in order
  std::vector<std::size_t> ok_index;        ///< sample index of each ok sample
  std::size_t completed = 0;                ///< samples [0, completed) ran
  bool interrupted = false;
  int signal = 0;
  std::string stop_reason;
};

/// How SeekerLosStudy::run is driven: over MPI ranks (a run's main loop only), with a
/// stop rule (convergence.h) checked on rank 0 after each block, and where the per-sample
/// grid values go.
struct SeekerRunControl {
  bool distributed = false;
  /// The pooled field figures and per-point maps need every grid value: they are written to
  /// `field_file` (a run's samples.h5; "" = a temporary file, removed after the run) as the
  /// samples stream in, and read back column by column. false: no grid value is kept (callers
  /// that use only the per-sample outputs).
  bool field_statistics = true;
  std::string field_file;
  /// The grid values are kept in memory for the field statistics when all planned samples'
  /// take at most this many bytes: nothing is read back, and without a field_file no file is
  /// written. Larger runs stream (memory independent of the sample count).
  std::size_t keep_grid_bytes = kKeepColumnsBytes;
  std::map<std::string, std::string> field_attributes;             ///< root attributes of the file
  std::map<std::string, std::uint64_t> field_number_attributes;
  std::function<std::string(const std::vector<std::vector<double>>& values, const std::vector<std::size_t>& ok_index,
                            std::size_t failures, std::size_t completed)>
      stop;
};

/// A run that keeps only the per-sample outputs: no grid value stored, no pooled figure or map.
inline SeekerRunControl outputs_only() {
  SeekerRunControl c;
  c.field_statistics = false;
  return c;
}

/// A study ready to run: model, sampler, design and grid built and validated.
class SeekerLosStudy {
 public:
  SeekerLosStudy(StudyConfig config, SeekerModel model, std::size_t samples, std::uint64_t seed);

  const StudyConfig& config() const { return config_; }
  const SeekerModel& model() const { return model_; }
  const SeekerSampler& sampler() const { return sampler_; }
  const models::LosGrid& grid() const { return grid_; }
  double requirement_rad() const { return requirement_rad_; }
  std::size_t samples() const { return samples_; }
  std::uint64_t seed() const { return seed_; }

  struct Workspace {
    std::vector<double> u;
    models::LosGrid::Workspace grid;
    std::vector<models::PointingError> errors;
  };
  Workspace make_workspace() const;
  /// Computes sample i alone (replay); depends only on (seed, samples, method, i).
  void compute(std::size_t i, Workspace& ws, SeekerSampleResult& out) const;
  /// The per-sample outputs (kSeekerOutputs order, into `outputs`) of one error realization
  /// and, unless `grid_total_arcsec` is empty, the total error at each grid point. Throws
  /// poise::Error for a non-finite pointing error.
  void evaluate_state(const models::SeekerErrorState& state, Workspace& ws, std::span<double> outputs,
                      std::span<float> grid_total_arcsec) const;
  /// The grid values' layout in samples.h5: one column per grid point, its yaw and pitch.
  WideColumnsSpec field_spec() const;
  /// Per-grid-point errors of sample i (for replay reports).
  std::vector<models::PointingError> grid_errors(std::size_t i) const;

  /// Runs all samples on `threads` threads; each finished block goes to `sink` in order.
  SeekerMcResult run(int threads, bool progress,
                     const std::function<void(std::span<const SeekerSampleResult>)>& sink,
                     const SeekerRunControl& control = {}) const;

 private:
  StudyConfig config_;
  SeekerModel model_;
  SeekerSampler sampler_;
  std::size_t samples_;
  std::uint64_t seed_;
  sampling::Design design_;
  models::LosGrid grid_;
  double requirement_rad_;
};

}  // namespace poise::studies
