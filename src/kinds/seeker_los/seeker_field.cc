#include "kinds/seeker_los/seeker_field.h"

#include <unistd.h>

#include <algorithm>
#include <any>
#include <cstring>
#include <filesystem>
#include <optional>

#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include "core/diagnostics.h"
#include "core/error.h"
#include "engine/results/field_statistics.h"
#include "sampling/distributed.h"

namespace poise::kinds::seeker_los {
using namespace poise::engine;
namespace {
namespace fs = std::filesystem;
// The field maps: p50, p95 and p99.73 of each grid point.
constexpr double kMapQuantiles[] = {0.5, 0.95, 0.9973};

// A file name for grid values no one keeps: in the system's temporary folder, unique.
std::string temporary_field_file() {
  std::string name = (fs::temp_directory_path() / "poise-field-XXXXXX").string();
  const int fd = mkstemp(name.data());
  require(fd >= 0, "cannot create a temporary file in " + fs::temp_directory_path().string());
  close(fd);
  return name;
}

// The field's per-point p50, p95 and p99.73 and its pooled statistics, from the writer's kept
// columns or else read back from `path` point by point (a rank without the writer reads the
// file); shared among the MPI ranks with `share`.
FieldStatistics field_statistics_of(const WideColumnsWriter* field, const std::string& path,
                                    const WideColumnsSpec& layout, int threads, const FieldShare* share) {
  std::optional<WideColumnsReader> reader;
  if (!field || !field->keeps()) reader.emplace(path, layout.dataset);
  return field_statistics(
      layout.columns,
      [&](std::size_t p, std::vector<float>& column) -> std::span<const float> {
        if (!reader) return field->kept_column(p);
        reader->read_column(p, column);
        return column;
      },
      kMapQuantiles, threads, kFieldCollectLimit, share);
}

SeekerFieldFigures figures_of(FieldStatistics&& fs) {
  SeekerFieldFigures f;
  f.present = true;
  f.p50 = std::move(fs.per_point[0]);
  f.p95 = std::move(fs.per_point[1]);
  f.p99_73 = std::move(fs.per_point[2]);
  f.pooled = fs.pooled;
  return f;
}

// An MPI run whose grid values go to samples.h5 makes the maps on all its ranks, each rank its
// own range of points (FieldShare): rank 0 sends each rank its columns when it keeps them in
// memory, else every rank reads its own from samples.h5 once rank 0 has closed it. Called on
// every rank; `field` only on rank 0. Returns rank 0's figures.
std::optional<SeekerFieldFigures> shared_field_figures(const WideColumnsWriter* field, const WideColumnsSpec& layout,
                                                       const std::string& samples_h5, std::size_t n_ok, int threads) {
  using sampling::Cluster;
  const bool root = Cluster::root();
  if (!Cluster::any(root && n_ok > 0)) return std::nullopt;  // also: samples.h5 is closed
  const std::size_t points = layout.columns;
  const bool from_memory = Cluster::any(root && field->keeps());
  const FieldShare share{Cluster::rank(), Cluster::size(),
                         [](const std::string& mine) { return Cluster::all_gather(mine); }};
  const auto first_of = [&](int rank) {
    return points * static_cast<std::size_t>(rank) / static_cast<std::size_t>(share.ranks);
  };
  if (!from_memory) {  // rank 0 named the run's folder: its samples.h5, absolute
    const std::string path = Cluster::broadcast(root ? fs::absolute(samples_h5).string() : std::string());
    FieldStatistics fs = field_statistics_of(field, path, layout, threads, &share);
    if (root) return figures_of(std::move(fs));
    return std::nullopt;
  }
  if (root) {
    for (int q = 1; q < share.ranks; ++q) {
      for (std::size_t p = first_of(q); p < first_of(q + 1); ++p) {
        const std::span<const float> column = field->kept_column(p);
        Cluster::send_to(q, std::string_view(reinterpret_cast<const char*>(column.data()), column.size_bytes()));
      }
    }
    return figures_of(field_statistics_of(field, samples_h5, layout, threads, &share));
  }
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
  return std::nullopt;
}

// The interrupted run's grid values of samples [0, done.size()) row by row into `writer`, if
// its file holds them with the samples' ok flags; false (nothing appended) if not.
bool copy_interrupted_rows(const std::string& path, const WideColumnsSpec& layout, std::span<const SampleResult> done,
                           WideColumnsWriter& writer) {
  std::optional<WideColumnsReader> old;
  try {
    if (!fs::exists(path)) return false;
    old.emplace(path, layout.dataset);
    if (old->rows() < done.size() || old->columns() != layout.columns) return false;
    const std::vector<std::uint8_t> ok = old->ok();
    for (std::size_t i = 0; i < done.size(); ++i) {
      if (ok.size() <= i || (ok[i] != 0) != done[i].ok) return false;
    }
  } catch (const Error&) {
    return false;  // a file cut short (kill -9): its values are recomputed
  }
  std::vector<float> rows;
  for (std::size_t first = 0; first < done.size(); first += kWideChunkRows) {
    const std::size_t n = std::min(kWideChunkRows, done.size() - first);
    old->read_rows(first, n, rows);
    for (std::size_t k = 0; k < n; ++k) {
      writer.append(first + k, done[first + k].ok,
                    std::span<const float>(rows.data() + k * layout.columns, layout.columns));
    }
  }
  return true;
}

}  // namespace

const SeekerFieldFigures* field_figures_of(const McResult& mc) {
  const auto* f = std::any_cast<SeekerFieldFigures>(&mc.study_figures);
  return f && f->present ? f : nullptr;
}

SeekerFieldRecorder::SeekerFieldRecorder(WideColumnsSpec layout, const SeekerFieldSettings& settings,
                                         const RunControl& control, std::size_t samples, std::size_t resumed,
                                         int threads)
    : layout_(std::move(layout)), settings_(settings), control_(control), threads_(threads) {
  // The grid values go to the run's samples.h5 (every rank knows whether they do: the maps of
  // an MPI run are shared then); without one they are only kept in memory when they fit, else
  // in an uncompressed scratch file read back once.
  settings_.values = settings.values && control.folder && !control.folder->samples_h5.empty();
  const bool root = !control.distributed || sampling::Cluster::root();
  if (!control.folder || !(settings.values || settings.maps) || !root) return;
  layout_.keep_up_to_bytes = settings.maps ? settings.keep_bytes : 0;
  temporary_ = !settings_.values && !fits_in_memory(layout_, samples);
  path_ = temporary_ ? temporary_field_file() : settings_.values ? control.folder->samples_h5 : std::string();
  if (settings_.values && resumed > 0) {
    // The interrupted run's file stays aside until its rows are copied (a restore cut short
    // leaves it there for the next --resume).
    interrupted_path_ = path_ + ".interrupted";
    std::error_code ec;
    if (!fs::exists(interrupted_path_, ec) && fs::exists(path_, ec)) fs::rename(path_, interrupted_path_);
  }
  layout_.compress = !temporary_;
  layout_.spread_compression = control.distributed && sampling::Cluster::size() > 1;
  writer_ = std::make_unique<WideColumnsWriter>(path_, layout_, samples, control.folder->text_attributes,
                                                control.folder->number_attributes, threads);
}

SeekerFieldRecorder::~SeekerFieldRecorder() {
  writer_.reset();
  std::error_code ec;
  if (temporary_) fs::remove(path_, ec);  // however the run ends
}

void SeekerFieldRecorder::restore(std::span<const SampleResult> done, const Recompute& recompute, bool progress) {
  if (!writer_ || done.empty()) return;
  if (!interrupted_path_.empty() && copy_interrupted_rows(interrupted_path_, layout_, done, *writer_)) {
    std::error_code ec;
    fs::remove(interrupted_path_, ec);
    return;
  }
  if (progress) {
    diagnostics::progress("  resuming: the grid values of the " + std::to_string(done.size()) +
                          " finished samples are not in the interrupted run's samples.h5; recomputing them");
  }
  std::vector<SampleResult> block;
  for (std::size_t first = 0; first < done.size(); first += kWideChunkRows) {
    const std::size_t n = std::min(kWideChunkRows, done.size() - first);
    recompute(first, n, block);
    append(std::span<const SampleResult>(block.data(), n));
  }
  std::error_code ec;
  if (!interrupted_path_.empty()) fs::remove(interrupted_path_, ec);
}

void SeekerFieldRecorder::append(std::span<const SampleResult> block) {
  if (!writer_) return;
  for (const auto& s : block) writer_->append(s.index, s.ok, s.field);
}

void SeekerFieldRecorder::finish(std::size_t n_ok, const std::function<void()>& summarize, McResult& r) {
  // The field maps of an MPI run whose grid values go to samples.h5 are made by all its ranks;
  // else by this process alone (from the file, its copy in memory or a scratch file).
  const bool shared_maps = control_.distributed && sampling::Cluster::size() > 1 && settings_.values && settings_.maps;
  // The tail on all threads, two independent halves side by side so that each fills the
  // other's serial moments: closing samples.h5 and the field figures read back point by point;
  // the per-sample outputs' summaries. With maps shared by the ranks, the other ranks start on
  // theirs once samples.h5 is closed, and rank 0 summarizes the outputs after the maps, while
  // they go on to the sweeps.
  SeekerFieldFigures figures;
  tbb::task_arena arena(std::max(1, threads_));
  arena.execute([&] {
    tbb::parallel_invoke(
        [&] {
          if (!writer_) return;
          const nlohmann::json file = writer_->close();
          r.samples_h5 = settings_.values ? file : nlohmann::json(nullptr);
          if (!shared_maps && n_ok > 0 && settings_.maps) {
            figures = figures_of(field_statistics_of(writer_.get(), path_, layout_, threads_, nullptr));
          }
          if (temporary_) {
            std::error_code ec;
            fs::remove(path_, ec);  // here, beside the summaries; the destructor if a step throws
          }
        },
        [&] {
          if (!shared_maps) summarize();
        });
  });
  if (shared_maps) {
    if (auto f = shared_field_figures(writer_.get(), layout_, control_.folder->samples_h5, n_ok, threads_)) {
      figures = std::move(*f);
    }
    arena.execute(summarize);
  }
  figures.present = writer_ && settings_.maps;
  r.study_figures = std::move(figures);
}

}  // namespace poise::kinds::seeker_los
