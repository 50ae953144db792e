#pragma once
/// What the geometry study runners (geometry_mass_runner, obstruction_runner) share: the run's
/// size and folder, the sample loop streaming samples.csv, the common parts of summary.json,
/// the report's last step and replay's JSON. Each runner keeps only its model, its outputs
/// and its own tables and plots.
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "sampling/design.h"
#include "geometry_studies/geometry_report.h"
#include "model_files/seeker_model.h"
#include "engine/output_spec.h"
#include "engine/study_config.h"
#include "engine/study_runner.h"

namespace poise::studies {

/// One per-sample output: its column in samples.csv and its entry in summary.json.
using GeometryOutputDef = OutputDeclaration;

/// One sample: drawn inputs and outputs (NaN when it failed, with the reason).
struct GeometrySample {
  std::size_t index = 0;
  bool ok = true;
  std::string message;
  std::vector<double> inputs, outputs;
};

/// Fills `out` for sample i: the design's point u in the unit hypercube, then
/// `evaluate(u, out.inputs)` draws the inputs and returns the outputs. An exception marks the
/// sample failed, with its message and `num_outputs` NaN outputs.
template <class Evaluate>
void compute_geometry_sample(std::size_t i, const sampling::Design& design, std::size_t dimension,
                             std::size_t num_outputs, GeometrySample& out, Evaluate&& evaluate) {
  out = GeometrySample{};
  out.index = i;
  out.inputs.assign(dimension, 0.0);
  std::vector<double> u(dimension);
  design.point(i, u);
  try {
    out.outputs = evaluate(std::span<const double>(u), out.inputs);
  } catch (const std::exception& ex) {
    out.ok = false;
    out.message = ex.what();
    out.outputs.assign(num_outputs, std::nan(""));
  }
}

struct GeometryRunSize {
  std::size_t samples = 0;
  std::uint64_t seed = 0;
  int threads = 1;
};

/// Sample count, seed and threads from the options over the study. Throws on --resume (with
/// `resume_message`), --until and on zero samples. For `poise sensitivity` it sets `cfg` up
/// for the Saltelli layout (base x (dimension + 2) samples; `dimension()` is the study's).
GeometryRunSize geometry_run_size(StudyConfig& cfg, const RunOptions& options, const std::string& resume_message,
                                  const std::function<std::size_t()>& dimension);

struct GeometryRun {
  GeometryRunSize size;
  std::string dir;      ///< run folder
  std::string started;  ///< ISO 8601
  std::chrono::steady_clock::time_point t0;
  bool plots = true;    ///< the run draws plots (gnuplot)
};

/// Creates the run folder, prints the progress line and starts the clock.
GeometryRun start_geometry_run(const StudyConfig& cfg, const RunOptions& options, const GeometryRunSize& size);

struct GeometrySampleResults {
  std::vector<std::vector<double>> values;  ///< per output, over the samples that passed
  std::vector<std::size_t> ok_index;        ///< their sample indices
  std::size_t completed = 0;                ///< samples run (fewer when stopped)
  std::string status = "complete";          ///< complete | interrupted | failed
  std::string stop_reason;
  int signal = 0;
  std::size_t failures = 0;
  nlohmann::json failed = nlohmann::json::array();  ///< the first 100 failures
  double wall_s = 0;                                ///< since the run's start, at the loop's end
};

/// Computes every sample in blocks on the run's threads and streams samples.csv in sample
/// order; `on_ok` sees each sample that passed, in order (for the runner's plot data). A
/// signal stops it after the block in flight, and so does a failure share above
/// [sampling] max_failure_share (sample_driver.h, convergence.h).
GeometrySampleResults run_geometry_samples(const StudyConfig& cfg, const GeometryRun& run,
                                           const std::vector<InputColumn>& inputs,
                                           std::span<const GeometryOutputDef> outputs,
                                           const std::function<void(std::size_t, GeometrySample&)>& compute,
                                           const std::function<void(const GeometrySample&)>& on_ok);

/// summary.json's "study" section.
nlohmann::json geometry_study_json(const StudyConfig& cfg, const std::string& model_name, const std::string& model_source);
/// summary.json's "sampling" section (a runner may add to it).
nlohmann::json geometry_sampling_json(const StudyConfig& cfg, const GeometryRun& run, std::size_t dimension);

/// Adds "outputs", "failures", "sample_convergence", "status", the Sobol indices of a sensitivity
/// run and "provenance" to `summary` and writes summary.json; `groups` names the design's
/// dimensions. Throws Interrupted or Error (finish_run_status) after the report when the run
/// stopped early: call finish_geometry_status after the report.
void write_geometry_summary(nlohmann::json& summary, const StudyConfig& cfg, const GeometryRun& run,
                            std::span<const GeometryOutputDef> outputs, const GeometrySampleResults& results,
                            const std::vector<InputColumn>& groups);

/// Writes plots/ and report.html (write_geometry_report) and prints the progress line; then
/// ends an interrupted or failed run with its error (finish_run_status).
/// The distribution figures of the main outputs (engine/report_figures.h) come from `results`.
void finish_geometry_report(const StudyConfig& cfg, const RunOptions& options, const GeometryRun& run,
                            const nlohmann::json& summary, std::vector<std::string> tables,
                            std::vector<GeometryPlot> plots, const GeometrySampleResults& results,
                            std::span<const GeometryOutputDef> outputs);

/// Sample count of a replay; throws if `index` is outside it.
std::size_t geometry_replay_samples(const StudyConfig& cfg, std::size_t index, const RunOptions& options);
/// One replayed sample as JSON: sample, status, message, inputs and outputs by name.
nlohmann::json geometry_replay_json(std::size_t index, const GeometrySample& r, const std::vector<InputColumn>& inputs,
                                    std::span<const GeometryOutputDef> outputs);

/// A number for the report's tables: %.*g.
std::string fmt_g(double v, int prec = 6);

}  // namespace poise::studies
