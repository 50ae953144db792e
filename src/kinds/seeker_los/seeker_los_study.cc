#include "kinds/seeker_los/seeker_los_study.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>
#include "core/units.h"

#include "engine/results/field_statistics.h"
#include "engine/run/convergence.h"
#include "engine/run/sample_driver.h"
#include "kinds/seeker_los/seeker_los_sections.h"
#include "sampling/distributed.h"
#include "sampling/progress.h"

namespace poise::kinds::seeker_los {
using namespace poise::model_files;
using namespace poise::geometry_studies;
using namespace poise::engine;
namespace {
constexpr double kArcsec = units::kArcsecPerRad;
// The field maps: p50, p95 and p99.73 of each grid point (McResult::field).
constexpr double kMapQuantiles[] = {0.5, 0.95, 0.9973};
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
  for (const auto& c : sampler_.columns()) input_names_.push_back(c.name);
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

namespace {

// A file name for grid values no one keeps: in the system's temporary folder, unique.
// TemporaryFile removes it however the run ends.
struct TemporaryFile {
  std::string path;
  ~TemporaryFile() {
    std::error_code ec;
    if (!path.empty()) std::filesystem::remove(path, ec);
  }
};

std::string temporary_field_file() {
  std::string name = (std::filesystem::temp_directory_path() / "poise-field-XXXXXX").string();
  const int fd = mkstemp(name.data());
  require(fd >= 0, "cannot create a temporary file in " + std::filesystem::temp_directory_path().string());
  close(fd);
  return name;
}

}  // namespace

SampleResult SeekerLosStudy::replay(std::size_t i) const {
  Workspace ws = make_workspace();
  SampleResult r;
  compute(i, ws, r);
  return r;
}

namespace {

// The field's per-point p50, p95 and p99.73 and its pooled statistics, from the writer's kept
// columns or else read back from `path` point by point (a rank without the writer reads the
// file); shared among the MPI ranks with `share`.
FieldStatistics field_figures(const WideColumnsWriter* field, const std::string& path, const WideColumnsSpec& layout,
                              std::size_t points, int threads, const FieldShare* share) {
  std::optional<WideColumnsReader> reader;
  if (!field || !field->keeps()) reader.emplace(path, layout.dataset);
  return field_statistics(
      points,
      [&](std::size_t p, std::vector<float>& column) -> std::span<const float> {
        if (!reader) return field->kept_column(p);
        reader->read_column(p, column);
        return column;
      },
      kMapQuantiles, threads, kFieldCollectLimit, share);
}

void keep_field_figures(FieldStatistics&& fs, McResult& r) {
  r.field.p50 = std::move(fs.per_point[0]);
  r.field.p95 = std::move(fs.per_point[1]);
  r.field.p99_73 = std::move(fs.per_point[2]);
  r.field.pooled = fs.pooled;
}

// Closes the grid values' file and, for the field maps made by this process alone, reads it
// back into them; a scratch file (temporary) is removed.
void close_field_file(WideColumnsWriter& field, const WideColumnsSpec& layout, const std::string& field_path,
                      bool temporary, std::size_t points, bool maps_here, int threads, McResult& r) {
  r.field.file = field.close();
  if (maps_here) keep_field_figures(field_figures(&field, field_path, layout, points, threads, nullptr), r);
  if (temporary) {
    r.field.file = nullptr;  // a scratch file, not the run's
    std::error_code ec;
    std::filesystem::remove(field_path, ec);  // here, beside the summaries; `scratch` if a step throws
  }
}

// An MPI run whose grid values go to samples.h5 makes the maps on all its ranks, each rank its
// own range of points (FieldShare): rank 0 sends each rank its columns when it keeps them in
// memory, else every rank reads its own from samples.h5 once rank 0 has closed it. Called on
// every rank; `field` only on rank 0.
void shared_field_figures(const WideColumnsWriter* field, const WideColumnsSpec& layout, const RunControl& control,
                          std::size_t points, std::size_t n_ok, int threads, McResult& r) {
  using sampling::Cluster;
  const bool root = Cluster::root();
  if (!Cluster::any(root && n_ok > 0)) return;  // also: samples.h5 is closed
  const bool from_memory = Cluster::any(root && field->keeps());
  const FieldShare share{Cluster::rank(), Cluster::size(),
                         [](const std::string& mine) { return Cluster::all_gather(mine); }};
  const auto first_of = [&](int rank) {
    return points * static_cast<std::size_t>(rank) / static_cast<std::size_t>(share.ranks);
  };
  if (!from_memory) {  // rank 0 named the run's folder: its samples.h5, absolute
    const std::string path =
        Cluster::broadcast(root ? std::filesystem::absolute(control.field_file).string() : std::string());
    FieldStatistics fs = field_figures(field, path, layout, points, threads, &share);
    if (root) keep_field_figures(std::move(fs), r);
  } else if (root) {
    for (int q = 1; q < share.ranks; ++q) {
      for (std::size_t p = first_of(q); p < first_of(q + 1); ++p) {
        const std::span<const float> column = field->kept_column(p);
        Cluster::send_to(q, std::string_view(reinterpret_cast<const char*>(column.data()), column.size_bytes()));
      }
    }
    keep_field_figures(field_figures(field, control.field_file, layout, points, threads, &share), r);
  } else {
    std::vector<std::vector<float>> columns(first_of(share.rank + 1) - first_of(share.rank));
    for (auto& column : columns) {
      const std::string bytes = Cluster::receive_from_root();
      column.resize(bytes.size() / sizeof(float));
      std::memcpy(column.data(), bytes.data(), column.size() * sizeof(float));
    }
    field_statistics(
        points,
        [&](std::size_t p, std::vector<float>&) -> std::span<const float> { return columns[p - first_of(share.rank)]; },
        kMapQuantiles, threads, kFieldCollectLimit, &share);
  }
}

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

}  // namespace

McResult SeekerLosStudy::run(int threads, bool progress, const SampleSink& sink, std::span<const SampleResult>,
                             const RunControl& control) const {
  McResult r;
  r.n = samples_;
  r.replicate_size = config_.replicate_size;
  const std::size_t g = grid_.size();
  const bool writes = control.field_figures && (!control.distributed || sampling::Cluster::root());
  // The grid values go to the run's samples.h5; without one they are only kept in memory
  // when they fit, else in an uncompressed scratch file read back once.
  WideColumnsSpec layout = field_spec();
  layout.keep_up_to_bytes = control.field_maps ? seeker_sections(config_).grid_values_in_memory_mb << 20 : 0;
  const bool temporary = writes && control.field_file.empty() && !fits_in_memory(layout, samples_);
  const std::string field_path = !writes ? "" : temporary ? temporary_field_file() : control.field_file;
  const TemporaryFile scratch{temporary ? field_path : std::string()};
  std::unique_ptr<WideColumnsWriter> field;
  if (writes) {
    layout.compress = !temporary;
    layout.spread_compression = control.distributed && sampling::Cluster::size() > 1;
    field = std::make_unique<WideColumnsWriter>(field_path, layout, samples_, control.field_attributes,
                                                control.field_number_attributes, threads);
  }
  // The scalar columns, sized for every planned sample at once: a growing vector would hold
  // its old and new storage at once (3x); untouched pages (a run stopped early, MPI ranks
  // other than 0) take no memory.
  r.values.resize(kNumSeekerOutputs);
  for (auto& v : r.values) v.reserve(samples_);
  r.ok_index.reserve(samples_);

  sampling::Progress bar("samples", samples_, progress && (!control.distributed || sampling::Cluster::root()));
  DriveSpec spec{0, samples_, config_.block, 16, threads, control.distributed};
  const DriveOutcome outcome = drive_samples<SampleResult>(
      spec, [this] { return make_workspace(); },
      [this](std::size_t i, Workspace& ws, SampleResult& res) { compute(i, ws, res); },
      [&](std::span<const SampleResult> block) { return sink.bytes(block); },
      [&](std::size_t, std::span<const SampleResult> block, std::string_view formatted) {
        if (sink) sink.write(block, formatted);
        if (field) {
          for (const auto& s : block) field->append(s.index, s.ok, s.field);
        }
        collect_samples(r, block);
      },
      [&](std::size_t) { return control.stop ? control.stop(r) : std::string(); }, encode_result, decode_result, &bar);
  bar.finish();
  if (control.samples_done) control.samples_done(outcome.interrupted);
  r.completed = outcome.completed;
  r.interrupted = outcome.interrupted;
  r.signal = outcome.signal;
  r.stop_reason = outcome.stop_reason;
  const std::size_t n_ok = r.ok_index.size();
  // The field maps of an MPI run whose grid values go to samples.h5 are made by all its ranks;
  // else by this process alone (from the file, its copy in memory or a scratch file).
  const bool shared_maps = control.distributed && sampling::Cluster::size() > 1 && control.field_figures &&
                           control.field_maps && !control.field_file.empty();
  r.field.present = writes && control.field_maps;
  // The tail on all threads, two independent halves side by side so that each fills the
  // other's serial moments: closing samples.h5 and the field figures read back point by point;
  // the per-sample outputs' summaries. With maps shared by the ranks, the other ranks start on
  // theirs once samples.h5 is closed, and rank 0 summarizes the outputs after the maps, while
  // they go on to the sweeps.
  const auto summarize = [&] { summarize_seeker_outputs(r, config_.replicate_size); };
  tbb::task_arena arena(std::max(1, threads));
  arena.execute([&] {
    tbb::parallel_invoke(
        [&] {
          if (field) {
            const bool maps_here = !shared_maps && n_ok > 0 && control.field_maps;
            close_field_file(*field, layout, field_path, temporary, g, maps_here, threads, r);
          }
        },
        [&] {
          if (!shared_maps) summarize();
        });
  });
  if (shared_maps) {
    shared_field_figures(field.get(), layout, control, g, n_ok, threads, r);
    arena.execute(summarize);
  }
  r.wall_seconds = bar.elapsed_seconds();
  return r;
}

}  // namespace poise::kinds::seeker_los
