#include "studies/gimbal_runner.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <thread>

#include "core/units.h"
#include "core/version.h"
#include "studies/gimbal_study.h"
#include "studies/procedure_runner.h"

namespace poise::studies {
namespace {
using nlohmann::json;
}  // namespace

std::string validate_gimbal_study(const StudyConfig& cfg) {
  const GimbalModel model = load_gimbal_model(cfg.model_path, cfg.overrides);
  GimbalStudy study(cfg, model, cfg.samples, cfg.seed);
  std::size_t tests = 0, positions = 0;
  for (const auto& g : cfg.groups) {
    tests += g.repeats * g.loads.size();
    positions += g.repeats * g.loads.size() * g.positions;
  }
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%s: valid. Study '%s' (%s) on model '%s': %zu unit-scope random inputs, %s design, %zu "
                "samples, seed %llu; per sample %zu group(s), %zu simulated tests, %zu turntable positions.",
                cfg.file.c_str(), cfg.name.c_str(), cfg.kind.c_str(), model.name.c_str(), study.input_names().size(),
                sampling::to_string(cfg.method).c_str(), cfg.samples, static_cast<unsigned long long>(cfg.seed),
                cfg.groups.size(), tests, positions);
  return buf;
}

json replay_gimbal_sample(const StudyConfig& cfg, std::size_t index, const RunOptions& options) {
  const std::size_t n = options.samples.value_or(cfg.samples);
  if (index >= n) throw Error("sample index " + std::to_string(index) + " is outside 0.." + std::to_string(n - 1));
  const GimbalStudy study(cfg, load_gimbal_model(cfg.model_path, cfg.overrides), n, options.seed.value_or(cfg.seed));
  return replay_procedure_sample(study, index);
}

std::string run_gimbal_study(const StudyConfig& cfg, const RunOptions& options) {
  const GimbalModel model = load_gimbal_model(cfg.model_path, cfg.overrides);
  return run_procedure_study(
      cfg, [&](const StudyConfig& c, std::size_t n, std::uint64_t seed) { return std::make_unique<GimbalStudy>(c, model, n, seed); },
      options);
}


}  // namespace poise::studies
