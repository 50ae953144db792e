#pragma once
// Run options for the tests that run a study in process (the engine through a study kind).
#include <string>

#include "engine/run/study_runner.h"

namespace poise::test {

/// Run options for tests: a given folder and thread count, no progress, no plots.
inline engine::RunOptions quiet_run_options(const std::string& out, int threads) {
  engine::RunOptions o;
  o.out = out;
  o.threads = threads;
  o.progress = false;
  o.plots = false;
  return o;
}

}  // namespace poise::test
