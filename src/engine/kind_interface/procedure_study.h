#pragma once
/// What the result-folder writer (procedure_runner.h) needs from a Monte Carlo study of a
/// simulated procedure (the gimbal static-unbalance test, the balancing machine): named
/// inputs and outputs per sample, a parallel run that streams finished samples in order,
/// a single-sample replay and the study's own report sections.
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.h"

#include "engine/kind_interface/output_spec.h"
#include "engine/results/mc_result.h"
#include "engine/run/sample_driver.h"
#include "engine/study_files/study_config.h"
#include "sampling/progress.h"
#include "sampling/statistics.h"

namespace poise::engine {

/// An input as the drawing gives it: the limits a worst case is taken between (the tolerance
/// as written about its centre, or a range's min and max) and its distribution's mean and
/// standard deviation.
struct InputLimits {
  double lower = 0.0, upper = 0.0, mean = 0.0, sd = 0.0;
};

/// Where a run's finished samples go (samples.csv): `format` makes a block's bytes where the
/// block was computed (on whichever MPI rank, on its threads), and `write` takes the block and
/// those bytes on rank 0, in sample order; so the formatting is spread over the ranks and rank 0
/// only writes. Empty: the samples go nowhere but the run's statistics.
struct SampleSink {
  std::function<std::string(std::span<const SampleResult>)> format;
  std::function<void(std::span<const SampleResult>, std::string_view formatted)> write;
  explicit operator bool() const { return static_cast<bool>(write); }
  /// The block's bytes, or none without a sink.
  std::string bytes(std::span<const SampleResult> block) const { return format ? format(block) : std::string(); }
};

/// The run's result folder, for a study that writes per-sample values of its own beside
/// samples.csv (a field's value at every point, in samples.h5): where and with which root
/// attributes. Only the main run of `poise run` has one.
struct RunFolder {
  std::string samples_h5;
  std::map<std::string, std::string> text_attributes;
  std::map<std::string, std::uint64_t> number_attributes;
};

/// How a run is driven beyond its sample range: over MPI ranks (the run's main loop only)
/// and with a stop rule checked on rank 0 after each chunk on the results so far.
struct RunControl {
  bool distributed = false;
  std::size_t replicate_size = 0;    ///< set from the study's config by ProcedureStudyBase::run
  std::size_t samples_per_task = 1;  ///< set from the study by ProcedureStudyBase::run
  /// Samples per chunk of the sample order (the stop points, the unit of samples.csv's writes):
  /// 0 = 8 whole procedures, or 4 tasks' worth of cheap samples (run_procedure_samples).
  std::size_t chunk = 0;
  std::function<std::string(const McResult&)> stop;  ///< "" = go on
  /// The run's folder (none: the run is kept in memory: sweeps, contributions, the optimizer).
  std::optional<RunFolder> folder;
  /// The per-sample field sink: each chunk of finished samples (SampleResult::field) on rank 0
  /// in sample order, after samples.csv's sink. Empty: the fields go nowhere.
  std::function<void(std::span<const SampleResult>)> field_sink;
  /// false: run_procedure_samples leaves McResult::outputs empty, for a study that summarizes
  /// its outputs itself beside work of its own (its field's figures).
  bool summarize = true;
  /// Called on every rank once the samples are done, before the study's own tail (its
  /// statistics, its field's figures), with whether a signal stopped them; it may use the
  /// ranks' collectives (a run that lets the other ranks go on while rank 0 finishes).
  std::function<void(bool interrupted)> samples_done;
};

/// A SampleResult's trip between MPI ranks.
void encode_result(const SampleResult& r, ByteWriter& w);
void decode_result(ByteReader& rd, SampleResult& r);

/// Accumulates finished samples into an McResult (counts failures, keeps ok outputs).
void collect_samples(McResult& r, std::span<const SampleResult> block);
/// Statistics of every output once all samples are collected.
void summarize_outputs(McResult& r);

/// summary.json's statistics of each declared output of a run, with its unit (and, when asked,
/// its description), by name.
nlohmann::json outputs_json(const McResult& r, const std::vector<OutputSpec>& outputs, bool with_descriptions);
/// The values of a run's outputs by name, for requirements' verdicts (none for a name it lacks).
std::function<OutputValues(const std::string&)> requirement_values(const McResult& r,
                                                                   const std::vector<OutputSpec>& outputs,
                                                                   const StudyConfig& cfg);

/// A thread's workspace as a study's compute() takes it: the object a make_workspace() that
/// returns a pointer points to, or the workspace itself.
template <class W>
auto& workspace_of(W& w) {
  if constexpr (requires { *w; }) {
    return *w;
  } else {
    return w;
  }
}

/// The parallel run every procedure study shares: samples [done.size(), samples) in small
/// in-order blocks (whole procedures are slow: progress and the CSV move often), one
/// workspace per thread; `done` (a resumed run's samples) counted but not recomputed.
template <class MakeWorkspace, class Compute>
McResult run_procedure_samples(std::size_t samples, std::size_t block, int threads, bool progress,
                               const SampleSink& sink, std::span<const SampleResult> done, MakeWorkspace make_workspace,
                               Compute compute, const RunControl& control = {}) {
  McResult r;
  r.n = samples;
  r.replicate_size = control.replicate_size;
  r.ok_index.reserve(samples);  // untouched pages of a run stopped early take no memory
  // Chunks of 8 whole procedures (progress and samples.csv move often), of a few tasks' worth
  // for cheap or batched samples, or the study's own; the same for any thread or rank count
  // (the stop points).
  const std::size_t chunk = control.chunk > 0
                                ? control.chunk
                                : std::min<std::size_t>(block, std::max<std::size_t>(8, 4 * control.samples_per_task));
  const auto finish = [&] {
    if (control.summarize) summarize_outputs(r);
  };
  // A resumed run's samples pass the stop rule chunk by chunk as they did the first time, so
  // a run that had already met its stop point is not continued past it.
  for (std::size_t start = 0; start < done.size(); start += chunk) {
    collect_samples(r, done.subspan(start, std::min(chunk, done.size() - start)));
    if (control.stop && r.stop_reason.empty()) r.stop_reason = control.stop(r);
  }
  const std::size_t first = std::min(done.size(), samples);
  if (!r.stop_reason.empty()) {
    if (control.samples_done) control.samples_done(false);
    r.completed = first;
    finish();
    return r;
  }
  sampling::Progress bar("samples", samples - first, progress && (!control.distributed || sampling::Cluster::root()));
  DriveSpec spec{
      first, samples, chunk, std::max<std::size_t>(control.samples_per_task, 1), threads, control.distributed};
  const DriveOutcome o = drive_samples<SampleResult>(
      spec, make_workspace, [&](std::size_t i, auto& ws, SampleResult& res) { compute(i, workspace_of(ws), res); },
      [&](std::span<const SampleResult> finished) { return sink.bytes(finished); },
      [&](std::size_t, std::span<const SampleResult> finished, std::string_view formatted) {
        if (sink) sink.write(finished, formatted);
        if (control.field_sink) control.field_sink(finished);
        collect_samples(r, finished);
      },
      [&](std::size_t) { return control.stop ? control.stop(r) : std::string(); }, encode_result, decode_result, &bar);
  bar.finish();
  if (control.samples_done) control.samples_done(o.interrupted);
  r.wall_seconds = bar.elapsed_seconds();
  r.completed = o.completed;
  r.interrupted = o.interrupted;
  r.signal = o.signal;
  r.stop_reason = o.stop_reason;
  finish();
  return r;
}

class ProcedureStudy {
 public:
  virtual ~ProcedureStudy() = default;
  virtual const StudyConfig& config() const = 0;
  /// The per-sample inputs as declared (name, unit, description, tolerance), samples.csv order.
  virtual const std::vector<InputSpec>& inputs() const = 0;
  /// Their names, in the same order.
  virtual const std::vector<std::string>& input_names() const = 0;
  /// The per-sample outputs as declared (name, unit, description), in samples.csv order.
  virtual const std::vector<OutputSpec>& outputs() const = 0;
  /// Their names, in the same order.
  virtual const std::vector<std::string>& output_names() const = 0;
  virtual std::string model_name() const = 0;
  virtual std::string model_source() const = 0;
  /// Runs samples [done.size(), n); `done` (a resumed run's samples) are counted, not rerun.
  virtual McResult run(int threads, bool progress, const SampleSink& sink, std::span<const SampleResult> done,
                       const RunControl& control = {}) const = 0;
  /// Dimensions of the design point (for sensitivity indices: the first of input_names()
  /// unless a study says otherwise) and whether a sample has randomness of its own beyond
  /// its design point (per-test draws, noise).
  virtual std::vector<std::string> design_dimension_names() const = 0;
  /// The model's tolerance key of each design dimension ("" = a tolerance of its own, named
  /// by design_dimension_names()): a tolerance drawn in several columns (a magnitude and its
  /// angle, one per plate or axis) gets one closed Sobol group. Empty = every column its own.
  virtual std::vector<std::string> design_dimension_tolerances() const { return {}; }
  /// Every model tolerance the study samples, by key ("tolerances.kt_drift"), those drawn per
  /// test included (for contributions). Default: those of the design's dimensions.
  virtual std::vector<std::string> tolerance_keys() const { return design_dimension_tolerances(); }
  /// Default: none. A study whose samples draw beyond their design point (per-test draws,
  /// sensor noise) says so, and Sobol indices then give that randomness a group of its own.
  virtual bool has_own_randomness() const { return false; }
  /// The sources of that randomness, each drawn from its own stream keyed by
  /// Design::stream_index(i, source) (one Sobol group each); one entry = one stream for all.
  virtual std::vector<std::string> randomness_sources() const { return {"per-test draws, noise"}; }
  /// Sample i alone (depends only on seed, sample count, method and i).
  virtual SampleResult replay(std::size_t i) const = 0;
  /// Solver settings and counters for summary.json "solver" and the report's Solver section;
  /// null (the default, a closed-form study): neither, and samples.csv has no solver_steps.
  virtual nlohmann::json solver_json(const McResult&) const { return nullptr; }
  /// Whether samples are integrated by a solver (samples.csv then has solver_steps).
  virtual bool has_solver() const { return false; }
  /// Study-specific summary.json content (null if none), e.g. the nominal machine.
  virtual nlohmann::json details(const McResult&) const { return nullptr; }
  /// Whether outputs can be computed at input values a caller gives (evaluate_point); false
  /// (the default): this study's inputs do not determine a sample.
  virtual bool evaluates_inputs() const { return false; }
  /// The nominal unit's inputs (engine/kind_interface/input_evaluation.h), input_names() order.
  virtual std::vector<double> nominal_inputs() const { return {}; }
  /// Point k: inputs (input_names() order and units) -> outputs (outputs() order and units);
  /// k picks the draws of a study with randomness of its own. Throws poise::Error for a point
  /// without a physical answer. Called only when evaluates_inputs().
  virtual void evaluate_point(std::size_t /*k*/, std::span<const double> /*inputs*/,
                              std::span<double> /*outputs*/) const {}
  /// Points [0, n) at once (inputs n x input_names(), outputs n x outputs(), row-major):
  /// a point without a physical answer gets its reason in failures[point] and NaN outputs.
  /// Default: evaluate_point one at a time. Called only when evaluates_inputs().
  virtual void evaluate_points(std::span<const double> inputs, std::size_t n, std::span<double> outputs,
                               std::vector<std::string>& failures) const {
    const std::size_t p = n ? inputs.size() / n : 0, q = n ? outputs.size() / n : 0;
    failures.assign(n, "");
    for (std::size_t r = 0; r < n; ++r) {
      try {
        evaluate_point(r, inputs.subspan(r * p, p), outputs.subspan(r * q, q));
      } catch (const Error& e) {
        failures[r] = e.what();
        for (std::size_t k = 0; k < q; ++k) outputs[r * q + k] = NAN;
      }
    }
  }
  /// Samples per task of the parallel loop: 1 (the default) for whole procedures, more for a
  /// study whose samples are cheap or computed in batches.
  virtual std::size_t samples_per_task() const { return 1; }
  /// Each input's drawing limits, mean and standard deviation (input_names() order and
  /// units), for the worst-case, RSS and Monte Carlo figures side by side
  /// (engine/results/stack_up.h); empty (the default): the study has no such box.
  virtual std::vector<InputLimits> input_limits() const { return {}; }
  /// Study-specific figures (written into plots_dir; names of the SVGs made are appended to
  /// `figures`) and HTML sections for report.html.
  virtual void report_sections(const McResult&, const std::string& /*plots_dir*/, bool /*plots*/,
                               std::vector<std::string>& /*figures*/, std::ostringstream& /*html*/) const {}
};

/// run() and replay() of a study that has samples(), config(), make_workspace() and
/// compute(i, workspace, result) (CRTP): one implementation for every procedure study. It
/// holds the study's declared inputs (declare_input) and outputs (declare_outputs), which the
/// derived study declares in its constructor.
template <class Derived>
class ProcedureStudyBase : public ProcedureStudy {
 public:
  const std::vector<InputSpec>& inputs() const override { return inputs_; }
  const std::vector<std::string>& input_names() const override { return input_names_; }
  /// The model's tolerance key of each input column ("" for a derived column).
  const std::vector<std::string>& input_tolerances() const { return input_tolerances_; }
  const std::vector<OutputSpec>& outputs() const override { return outputs_; }
  const std::vector<std::string>& output_names() const override { return output_names_; }

  McResult run(int threads, bool progress, const SampleSink& sink, std::span<const SampleResult> done = {},
               const RunControl& control = {}) const override {
    const Derived& d = static_cast<const Derived&>(*this);
    RunControl c = control;
    c.replicate_size = d.config().replicate_size;
    c.samples_per_task = d.samples_per_task();
    return run_procedure_samples(
        d.samples(), d.config().block, threads, progress, sink, done, [&d] { return d.make_workspace(); },
        [&d](std::size_t i, auto& ws, SampleResult& res) { d.compute(i, ws, res); }, c);
  }
  std::vector<std::string> design_dimension_names() const override {
    const Derived& d = static_cast<const Derived&>(*this);
    std::vector<std::string> names(d.design_dimension());
    for (std::size_t k = 0; k < names.size(); ++k) {
      names[k] = k < d.input_names().size() ? d.input_names()[k] : "(unused dimension " + std::to_string(k) + ")";
    }
    return names;
  }
  std::vector<std::string> design_dimension_tolerances() const override {
    const Derived& d = static_cast<const Derived&>(*this);
    std::vector<std::string> keys(d.design_dimension());
    for (std::size_t k = 0; k < keys.size() && k < d.input_tolerances().size(); ++k) keys[k] = d.input_tolerances()[k];
    return keys;
  }
  SampleResult replay(std::size_t i) const override {
    const Derived& d = static_cast<const Derived&>(*this);
    auto ws = d.make_workspace();
    SampleResult r;
    d.compute(i, *ws, r);
    return r;
  }

 protected:
  /// A result slot made ready for sample i (the driver reuses its slots): ok, no message, every
  /// input and output NaN until computed, no solver counters, no field.
  void start_sample(std::size_t i, SampleResult& out) const {
    out.index = i;
    out.ok = true;
    out.message.clear();
    out.inputs.assign(input_names_.size(), NAN);
    out.outputs.assign(output_names_.size(), NAN);
    out.solver_steps = out.rhs_evals = 0;
    out.field.clear();
  }
  /// The outputs, declared once (their names follow).
  void declare_outputs(std::vector<OutputSpec> outputs) {
    outputs_ = std::move(outputs);
    output_names_ = output_names_of(outputs_);
  }
  /// The next input column, declared once (its name and tolerance key follow).
  void declare_input(InputSpec input) {
    input_names_.push_back(input.name);
    input_tolerances_.push_back(input.tolerance);
    inputs_.push_back(std::move(input));
  }

 private:
  std::vector<InputSpec> inputs_;
  std::vector<std::string> input_names_, input_tolerances_;
  std::vector<OutputSpec> outputs_;
  std::vector<std::string> output_names_;
};

}  // namespace poise::engine
