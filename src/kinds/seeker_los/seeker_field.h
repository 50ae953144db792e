#pragma once
/// The per-sample field of a seeker_los run: the total LOS error at every grid point of every
/// sample (SampleResult::field, arcsec), taken by the run's field sink (RunControl::field_sink)
/// in sample order. Its values go to the run's samples.h5 ([output] grid_values) or, for the
/// maps alone, stay in memory (a scratch file when they do not fit); its figures
/// (SeekerFieldFigures: each grid point's p50, p95 and p99.73, the pooled statistics) are made
/// from them once the samples are done, on all the run's threads and, in an MPI run that
/// writes samples.h5, on all its ranks.
///
/// A resumed run takes its finished samples' values from the interrupted run's samples.h5 (set
/// aside as samples.h5.interrupted until they are copied into the new file) and recomputes only
/// those it cannot find there (a file cut by kill -9; maps kept without grid_values).
#include <cstddef>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "engine/kind_interface/procedure_study.h"
#include "engine/results/mc_result.h"
#include "engine/results/wide_columns.h"
#include "sampling/statistics.h"

namespace poise::kinds::seeker_los {
using engine::McResult;
using engine::RunControl;
using engine::SampleResult;
using engine::WideColumnsSpec;
using engine::WideColumnsWriter;

/// The field's figures over a run's ok samples (McResult::study_figures of a seeker run).
struct SeekerFieldFigures {
  bool present = false;
  sampling::Summary pooled;              ///< over every (ok sample, grid point)
  std::vector<double> p50, p95, p99_73;  ///< per grid point, over the ok samples
};

/// The seeker's own figures of a run, or none (a run without maps, an in-memory run).
const SeekerFieldFigures* field_figures_of(const McResult& mc);

/// [output] grid_values, maps and grid_values_in_memory_mb of the study file.
struct SeekerFieldSettings {
  bool values = true;
  bool maps = true;
  std::size_t keep_bytes = 0;
};

class SeekerFieldRecorder {
 public:
  /// Samples [first, first + n) computed again into `out` (a resumed run's samples whose grid
  /// values were lost).
  using Recompute = std::function<void(std::size_t first, std::size_t n, std::vector<SampleResult>& out)>;

  /// A run of `samples` samples, `resumed` of them done before. Only a run with a folder keeps
  /// a field; only its rank 0 writes it.
  SeekerFieldRecorder(WideColumnsSpec layout, const SeekerFieldSettings& settings, const RunControl& control,
                      std::size_t samples, std::size_t resumed, int threads);
  ~SeekerFieldRecorder();
  SeekerFieldRecorder(const SeekerFieldRecorder&) = delete;
  SeekerFieldRecorder& operator=(const SeekerFieldRecorder&) = delete;

  /// Whether this process writes the field (and so has a sink).
  bool writes() const { return static_cast<bool>(writer_); }
  /// A resumed run's finished samples' values, before the new ones: from the interrupted run's
  /// samples.h5 when it holds them with the same ok flags, else from `recompute` (saying so
  /// with `progress`).
  void restore(std::span<const SampleResult> done, const Recompute& recompute, bool progress);
  /// The sink: a chunk of finished samples' grid values, in sample order.
  void append(std::span<const SampleResult> block);
  /// Once the samples are done (every rank): closes the file and makes the figures, beside
  /// `summarize` (the outputs' statistics) on the run's threads; sets r.study_figures and
  /// r.samples_h5 (rank 0). `n_ok`: ok samples (rank 0's count).
  void finish(std::size_t n_ok, const std::function<void()>& summarize, McResult& r);

 private:
  WideColumnsSpec layout_;
  SeekerFieldSettings settings_;
  const RunControl& control_;
  int threads_;
  bool temporary_ = false;
  std::string path_, interrupted_path_;
  std::unique_ptr<WideColumnsWriter> writer_;
};

}  // namespace poise::kinds::seeker_los
