#pragma once
/// A study kind whose samples are whole simulated procedures (engine/kind_interface/procedure_study.h):
/// the module makes one ProcedureStudy for a configuration, and the engine does the rest:
/// run (engine/run/procedure_runner.h: samples.csv streamed, resume, MPI, --until, summary,
/// report), replay, outputs with units, and the optimizer's in-memory evaluation.
#include <map>
#include <memory>
#include <string>

#include "engine/kind_interface/procedure_study.h"
#include "engine/kind_interface/study_kind.h"

namespace poise::engine {

class ProcedureKind : public StudyKind {
 public:
  /// The study of `cfg` on its model loaded with `model_overrides`, for `samples` samples
  /// and `seed` (a resumed run's may differ from the file's).
  virtual std::unique_ptr<ProcedureStudy> make_study(const StudyConfig& cfg,
                                                     const std::map<std::string, std::string>& model_overrides,
                                                     std::size_t samples, std::uint64_t seed) const = 0;

  std::vector<OutputSpec> outputs(const StudyConfig& cfg) const override;
  std::string run(const StudyConfig& cfg, const RunOptions& options) const override;
  nlohmann::json replay(const StudyConfig& cfg, std::size_t index, const RunOptions& options) const override;
  bool has_own_randomness(const StudyConfig& cfg) const override;
  /// Through the study's evaluate_point, if it evaluates inputs (else refused).
  std::unique_ptr<InputEvaluator> input_evaluator(const StudyConfig& cfg,
                                                  const std::map<std::string, std::string>& model_overrides,
                                                  std::uint64_t seed) const override;
  McResult evaluate(const StudyConfig& cfg, const std::map<std::string, std::string>& model_overrides,
                    std::size_t samples, std::uint64_t seed, int threads) const override;
};

/// The optimizer's view of one in-memory run of a procedure study.
McResult evaluate_procedure(const ProcedureStudy& study, int threads);

}  // namespace poise::engine
