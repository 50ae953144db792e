#include "kinds/seeker_los/seeker_los_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include "core/units.h"

#include "engine/run/convergence.h"
#include "engine/run/sample_driver.h"
#include "kinds/seeker_los/seeker_field.h"
#include "kinds/seeker_los/seeker_los_sections.h"

namespace poise::kinds::seeker_los {
using namespace poise::model_files;
using namespace poise::engine;
namespace {
constexpr double kArcsec = units::kArcsecPerRad;
}  // namespace

SeekerLosStudy::SeekerLosStudy(StudyConfig config, SeekerModel model, std::size_t samples, std::uint64_t seed)
    : config_(std::move(config)),
      model_(std::move(model)),
      sampler_(model_),
      samples_(samples),
      seed_(seed),
      design_(make_design(config_, seed, samples, sampler_.dimension())),
      grid_(models::linspace(model_.yaw_min, model_.yaw_max, seeker_sections(config_).yaw_points),
            models::linspace(model_.pitch_min, model_.pitch_max, seeker_sections(config_).pitch_points)),
      requirement_rad_(seeker_sections(config_).requirement_in_pixels
                           ? seeker_sections(config_).requirement * model_.pixel_ifov
                           : seeker_sections(config_).requirement) {
  for (std::size_t k = 0; k < sampler_.columns().size(); ++k) {
    const InputColumn& c = sampler_.columns()[k];
    inputs_.push_back({c.name, c.unit, "", sampler_.column_tolerances()[k]});
  }
  input_names_ = input_names_of(inputs_);
  append_outputs(outputs_, "", kSeekerOutputs);
  output_names_ = output_names_of(outputs_);
}

SeekerLosStudy::Workspace SeekerLosStudy::make_workspace() const {
  Workspace ws;
  ws.u.resize(sampler_.dimension());
  ws.grid = grid_.make_workspace();
  ws.errors.resize(grid_.size());
  return ws;
}

void SeekerLosStudy::compute(std::size_t i, Workspace& ws, SampleResult& out) const {
  out.index = i;
  out.ok = true;
  out.message.clear();
  out.inputs.assign(sampler_.dimension(), NAN);
  out.outputs.assign(kNumSeekerOutputs, NAN);
  out.field.assign(grid_.size(), NAN);
  try {
    design_.point(i, ws.u);
    evaluate_state(sampler_.draw(ws.u, out.inputs), ws, out.outputs, out.field);
  } catch (const std::exception& e) {
    out.ok = false;
    out.message = e.what();
  }
}

void SeekerLosStudy::evaluate_state(const models::SeekerErrorState& state, Workspace& ws, std::span<double> outputs,
                                    std::span<float> grid_total_arcsec) const {
  grid_.evaluate(state, ws.grid, ws.errors);
  double max_total = 0, sum_sq = 0, max_yaw = 0, max_pitch = 0;
  std::size_t ok_points = 0;
  for (std::size_t g = 0; g < ws.errors.size(); ++g) {
    const auto& e = ws.errors[g];
    if (!std::isfinite(e.total) || !std::isfinite(e.yaw) || !std::isfinite(e.pitch)) {
      throw Error("non-finite pointing error at grid point " + std::to_string(g));
    }
    max_total = std::max(max_total, e.total);
    sum_sq += e.total * e.total;
    max_yaw = std::max(max_yaw, std::abs(e.yaw));
    max_pitch = std::max(max_pitch, std::abs(e.pitch));
    ok_points += e.total <= requirement_rad_ ? 1 : 0;
    if (!grid_total_arcsec.empty()) grid_total_arcsec[g] = static_cast<float>(e.total * kArcsec);
  }
  const double n = static_cast<double>(ws.errors.size());
  const double values[kNumSeekerOutputs] = {
      max_total * kArcsec,         std::sqrt(sum_sq / n) * kArcsec, max_yaw * kArcsec,
      max_pitch * kArcsec,         max_total / model_.pixel_ifov,   static_cast<double>(ok_points) / n,
      max_yaw / model_.pixel_ifov, max_pitch / model_.pixel_ifov};
  std::copy(std::begin(values), std::end(values), outputs.begin());
}

std::vector<models::PointingError> SeekerLosStudy::grid_errors(std::size_t i) const {
  Workspace ws = make_workspace();
  design_.point(i, ws.u);
  std::vector<double> values(sampler_.dimension());
  grid_.evaluate(sampler_.draw(ws.u, values), ws.grid, ws.errors);
  return ws.errors;
}

WideColumnsSpec SeekerLosStudy::field_spec() const {
  WideColumnsSpec spec{"grid_total_arcsec",
                       "arcsec",
                       "total LOS pointing error of each sample (row) at each grid point (column)",
                       grid_.size(),
                       {}};
  ColumnCoordinate yaw{"grid_yaw_deg", "deg", "yaw gimbal angle of each column", {}};
  ColumnCoordinate pitch{"grid_pitch_deg", "deg", "pitch gimbal angle of each column", {}};
  for (std::size_t ia = 0; ia < grid_.alpha().size(); ++ia) {
    for (std::size_t ib = 0; ib < grid_.beta().size(); ++ib) {  // column grid_.index(ia, ib)
      yaw.values.push_back(grid_.alpha()[ia] / units::kRadPerDeg);
      pitch.values.push_back(grid_.beta()[ib] / units::kRadPerDeg);
    }
  }
  spec.coordinates = {yaw, pitch};
  return spec;
}

SampleResult SeekerLosStudy::replay(std::size_t i) const {
  Workspace ws = make_workspace();
  SampleResult r;
  compute(i, ws, r);
  return r;
}

namespace {

// The summaries of the per-sample outputs (none without an ok sample: also on MPI ranks other
// than 0, which keep no values), on the caller's threads.
void summarize_seeker_outputs(McResult& r, std::size_t replicate_size) {
  if (r.ok_index.empty()) return;
  r.outputs.resize(kNumSeekerOutputs);
  tbb::parallel_for(
      std::size_t{0}, kNumSeekerOutputs,
      [&](std::size_t k) { r.outputs[k] = summarize_output(r.values[k], r.ok_index, replicate_size); },
      tbb::simple_partitioner());
}

// The grid values of samples [first, first + n) again, on the caller's threads.
void recompute_samples(const SeekerLosStudy& study, std::size_t first, std::size_t n, int threads,
                       std::vector<SampleResult>& out) {
  out.resize(n);
  tbb::enumerable_thread_specific<SeekerLosStudy::Workspace> workspaces([&] { return study.make_workspace(); });
  tbb::task_arena(std::max(1, threads)).execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 16), [&](const tbb::blocked_range<std::size_t>& r) {
      samples_computed().fetch_add(r.size(), std::memory_order_relaxed);
      for (std::size_t k = r.begin(); k != r.end(); ++k) study.compute(first + k, workspaces.local(), out[k]);
    });
  });
}

}  // namespace

McResult SeekerLosStudy::run(int threads, bool progress, const SampleSink& sink, std::span<const SampleResult> done,
                             const RunControl& control) const {
  const SeekerLosSections& sec = seeker_sections(config_);
  SeekerFieldRecorder field(field_spec(), {sec.grid_values, sec.maps, sec.grid_values_in_memory_mb << 20}, control,
                            samples_, done.size(), threads);
  field.restore(
      done,
      [&](std::size_t first, std::size_t n, std::vector<SampleResult>& out) {
        recompute_samples(*this, first, n, threads, out);
      },
      progress);
  RunControl c = control;
  c.replicate_size = config_.replicate_size;
  c.samples_per_task = 16;
  c.chunk = config_.block;
  c.summarize = false;  // beside the field's figures, below
  if (field.writes()) c.field_sink = [&](std::span<const SampleResult> block) { field.append(block); };
  McResult r = run_procedure_samples(
      samples_, config_.block, threads, progress, sink, done, [this] { return make_workspace(); },
      [this](std::size_t i, Workspace& ws, SampleResult& res) { compute(i, ws, res); }, c);
  const auto tail = std::chrono::steady_clock::now();
  field.finish(
      r.ok_index.size(), [&] { summarize_seeker_outputs(r, config_.replicate_size); }, r);
  r.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - tail).count();
  return r;
}

}  // namespace poise::kinds::seeker_los
