#include "engine/kind_interface/input_evaluation.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <thread>

#include "core/error.h"
#include "engine/results/fault_injection.h"
#include "sampling/distributed.h"

namespace poise::engine {

InputColumns InputColumns::row_major(const double* matrix, std::size_t inputs) {
  InputColumns c;
  for (std::size_t j = 0; j < inputs; ++j) {
    c.data.push_back(matrix + j);
    c.stride.push_back(inputs);
  }
  return c;
}

InputEvaluationFailures evaluate_inputs(const InputEvaluator& evaluator, const InputColumns& inputs, std::size_t points,
                                        std::span<double> outputs, int threads) {
  const std::size_t ni = evaluator.input_names().size(), no = evaluator.outputs().size();
  if (inputs.data.size() != ni || inputs.stride.size() != ni || outputs.size() != points * no) {
    throw Error("evaluate: " + std::to_string(points) + " points need " + std::to_string(ni) +
                " input columns and room for " + std::to_string(points * no) + " outputs");
  }
  const int n_threads = threads > 0 ? threads : sampling::Cluster::default_threads();
  std::vector<std::pair<std::size_t, std::string>> failed;
  std::mutex failed_mutex;
  tbb::task_arena arena(n_threads);
  arena.execute([&] {
    // Chunks of 256 points: one virtual call and one workspace per chunk, not per point.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points, 256), [&](const tbb::blocked_range<std::size_t>& r) {
      // The chunk's inputs gathered row by row first: an evaluator then reads one row per
      // point, not one value from each of dozens of column arrays (which defeats the caches).
      std::vector<double> rows((r.end() - r.begin()) * ni);
      std::vector<std::pair<std::size_t, std::string>> local, not_finite;
      for (std::size_t j = 0; j < ni; ++j) {
        for (std::size_t k = r.begin(); k < r.end(); ++k) {
          const double x = inputs.at(j, k);
          rows[(k - r.begin()) * ni + j] = x;
          if (!std::isfinite(x))
            not_finite.emplace_back(k, "input " + evaluator.input_names()[j] + " is not a finite number");
        }
      }
      InputColumns chunk = InputColumns::row_major(rows.data(), ni);
      chunk.first = r.begin();
      fault_injection::hold_if_held_in(r.begin(), r.end());  // a test hook (fault_injection.h)
      evaluator.evaluate_points(chunk, outputs.data(), r.begin(), r.end(), local);
      // A point with a NaN or infinite input has no answer, whatever the formula made of it.
      for (const auto& [k, why] : not_finite) {
        std::fill(outputs.begin() + static_cast<std::ptrdiff_t>(k * no),
                  outputs.begin() + static_cast<std::ptrdiff_t>((k + 1) * no), NAN);
        std::erase_if(local, [k = k](const auto& f) { return f.first == k; });
      }
      std::sort(not_finite.begin(), not_finite.end());
      not_finite.erase(std::unique(not_finite.begin(), not_finite.end(),
                                   [](const auto& a, const auto& b) { return a.first == b.first; }),
                       not_finite.end());
      local.insert(local.end(), not_finite.begin(), not_finite.end());
      if (!local.empty()) {
        const std::lock_guard<std::mutex> lock(failed_mutex);
        failed.insert(failed.end(), local.begin(), local.end());
      }
    });
  });
  std::sort(failed.begin(), failed.end());
  InputEvaluationFailures f;
  f.count = failed.size();
  failed.resize(std::min<std::size_t>(failed.size(), 100));
  f.first = std::move(failed);
  return f;
}

}  // namespace poise::engine
