#pragma once
/// Runs work on `threads` threads: in the arena the caller is already in when that arena has
/// exactly that many, else in a new one. A new arena inside a task of another arena of the same
/// size would only get the calling thread (the others are busy in the outer one), so tails that
/// run side by side (tbb::parallel_invoke) share one arena instead.
#include <tbb/task_arena.h>

#include <algorithm>
#include <utility>

namespace poise::engine {

template <class Work>
void run_on_threads(int threads, Work&& work) {
  threads = std::max(1, threads);
  if (tbb::this_task_arena::max_concurrency() == threads) {
    std::forward<Work>(work)();
    return;
  }
  tbb::task_arena arena(threads);
  arena.execute(std::forward<Work>(work));
}

}  // namespace poise::engine
