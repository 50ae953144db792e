#pragma once
/// Runs per-sample work in parallel (oneTBB) and hands finished results to a sink
/// in sample order, block by block, so results stream to disk as they come and the
/// output is identical for any thread count.
///
///   Workspace: per-thread mutable state (buffers, solver memory), built once per thread.
///   compute(i, workspace, result): fills result for sample i; must depend only on i.
///   sink(first_index, results): called in order, on the calling thread, per block.
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

#include "sampling/progress.h"

namespace poise::sampling {

struct RunShape {
  std::size_t first = 0;      ///< first sample index (resume / replay)
  std::size_t count = 0;      ///< number of samples
  int threads = 1;            ///< worker threads (>= 1)
  std::size_t block = 1024;   ///< samples per in-order block
  /// Samples per parallel task; 1 for slow samples (a whole simulated procedure), so that
  /// even a small block spreads over every thread.
  std::size_t grain = 16;
};

template <class Result, class MakeWorkspace, class Compute, class Sink>
void run_in_blocks(const RunShape& shape, MakeWorkspace make_workspace, Compute compute, Sink sink,
                   Progress* progress = nullptr) {
  using Workspace = decltype(make_workspace());
  tbb::task_arena arena(std::max(1, shape.threads));
  tbb::enumerable_thread_specific<Workspace> workspaces(make_workspace);
  std::vector<Result> block(std::min(shape.block, std::max<std::size_t>(shape.count, 1)));
  for (std::size_t start = 0; start < shape.count; start += shape.block) {
    const std::size_t n = std::min(shape.block, shape.count - start);
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, std::max<std::size_t>(shape.grain, 1)),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          Workspace& ws = workspaces.local();
                          for (std::size_t k = r.begin(); k != r.end(); ++k) {
                            compute(shape.first + start + k, ws, block[k]);
                          }
                        });
    });
    sink(shape.first + start, std::span<const Result>(block.data(), n));
    if (progress) progress->update(start + n);
  }
}

}  // namespace poise::sampling
