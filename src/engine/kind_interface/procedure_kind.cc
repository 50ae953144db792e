#include "engine/kind_interface/procedure_kind.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "engine/run/procedure_runner.h"

namespace poise::engine {

std::vector<OutputSpec> ProcedureKind::outputs(const StudyConfig& cfg) const {
  return make_study(cfg, cfg.overrides, 1, cfg.seed)->outputs();
}

std::string ProcedureKind::run(const StudyConfig& cfg, const RunOptions& options) const {
  return run_procedure_study(
      cfg, [&](const StudyConfig& c, std::size_t n, std::uint64_t seed) { return make_study(c, c.overrides, n, seed); },
      options, requirements(cfg));
}

nlohmann::json ProcedureKind::replay(const StudyConfig& cfg, std::size_t index, const RunOptions& options) const {
  const std::size_t n = options.samples.value_or(cfg.samples);
  if (index >= n) throw UsageError("sample index " + std::to_string(index) + " is outside 0.." + std::to_string(n - 1));
  const auto study = make_study(cfg, cfg.overrides, n, options.seed.value_or(cfg.seed));
  return replay_procedure_sample(*study, index);
}

namespace {

// A procedure study's evaluate_point over a range of points.
class ProcedureInputEvaluator final : public InputEvaluator {
 public:
  explicit ProcedureInputEvaluator(std::unique_ptr<ProcedureStudy> study) : study_(std::move(study)) {}
  const std::vector<InputSpec>& inputs() const override { return study_->inputs(); }
  const std::vector<std::string>& input_names() const override { return study_->input_names(); }
  const std::vector<OutputSpec>& outputs() const override { return study_->outputs(); }
  std::vector<double> nominal_inputs() const override { return study_->nominal_inputs(); }
  bool has_own_randomness() const override { return study_->has_own_randomness(); }
  void evaluate_points(const InputColumns& inputs, double* values, std::size_t begin, std::size_t end,
                       std::vector<std::pair<std::size_t, std::string>>& failures) const override {
    evaluate_each_point(
        inputs, {}, input_names().size(), outputs().size(), values, begin, end, failures,
        [&](std::size_t k, std::span<const double> x, std::span<double> y) { study_->evaluate_point(k, x, y); });
  }

 private:
  std::unique_ptr<ProcedureStudy> study_;
};

}  // namespace

bool ProcedureKind::has_own_randomness(const StudyConfig& cfg) const {
  return make_study(cfg, cfg.overrides, 1, cfg.seed)->has_own_randomness();
}

std::unique_ptr<InputEvaluator> ProcedureKind::input_evaluator(
    const StudyConfig& cfg, const std::map<std::string, std::string>& model_overrides, std::uint64_t seed) const {
  auto overrides = cfg.overrides;
  for (const auto& [k, v] : model_overrides) overrides[k] = v;
  // One sample's study: the inputs are given, no design point is drawn (a study with draws of
  // its own keys them by the point index evaluate_point gets, not by a sample count).
  std::unique_ptr<ProcedureStudy> study = make_study(cfg, overrides, 1, seed);
  if (!study->evaluates_inputs()) return StudyKind::input_evaluator(cfg, model_overrides, seed);
  return std::make_unique<ProcedureInputEvaluator>(std::move(study));
}

McResult evaluate_procedure(const ProcedureStudy& study, int threads) {
  McResult e = study.run(threads, false, {}, {});
  e.names = study.output_names();
  e.values.resize(e.names.size());
  return e;
}

McResult ProcedureKind::evaluate(const StudyConfig& cfg, const std::map<std::string, std::string>& model_overrides,
                                 std::size_t samples, std::uint64_t seed, int threads) const {
  return evaluate_procedure(*make_study(cfg, model_overrides, samples, seed), threads);
}

}  // namespace poise::engine
