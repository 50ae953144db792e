#include "engine/procedure_kind.h"

#include "core/error.h"
#include "engine/procedure_runner.h"

namespace poise::studies {

std::vector<OutputSpec> ProcedureKind::outputs(const StudyConfig& cfg) const {
  return make_study(cfg, cfg.overrides, 1, cfg.seed)->outputs();
}

std::string ProcedureKind::run(const StudyConfig& cfg, const RunOptions& options) const {
  return run_procedure_study(
      cfg,
      [&](const StudyConfig& c, std::size_t n, std::uint64_t seed) { return make_study(c, c.overrides, n, seed); },
      options, requirements(cfg));
}

nlohmann::json ProcedureKind::replay(const StudyConfig& cfg, std::size_t index, const RunOptions& options) const {
  const std::size_t n = options.samples.value_or(cfg.samples);
  if (index >= n) throw UsageError("sample index " + std::to_string(index) + " is outside 0.." + std::to_string(n - 1));
  const auto study = make_study(cfg, cfg.overrides, n, options.seed.value_or(cfg.seed));
  return replay_procedure_sample(*study, index);
}

StudyEvaluation evaluate_procedure(const ProcedureStudy& study, int threads) {
  const McResult mc = study.run(threads, false, nullptr, {});
  StudyEvaluation e;
  e.names = study.output_names();
  e.values = mc.values;
  e.values.resize(e.names.size());
  e.ok_index = mc.ok_index;
  e.samples = mc.n;
  e.failures = mc.failures;
  if (!mc.failed.empty()) e.first_failure = mc.failed.front().second;
  e.wall_seconds = mc.wall_seconds;
  return e;
}

StudyEvaluation ProcedureKind::evaluate(const StudyConfig& cfg, const std::map<std::string, std::string>& model_overrides,
                                        std::size_t samples, std::uint64_t seed, int threads) const {
  return evaluate_procedure(*make_study(cfg, model_overrides, samples, seed), threads);
}

}  // namespace poise::studies
