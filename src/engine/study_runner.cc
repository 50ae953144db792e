#include "engine/study_runner.h"

#include "engine/references.h"
#include "engine/study_kind.h"
#include "sampling/distributed.h"

namespace poise::studies {

std::string validate_study(const std::string& study_path) {
  const StudyConfig cfg = load_study(study_path);
  const StudyKind& kind = study_kind(cfg.kind);
  std::string summary = kind.validate(cfg);
  const auto refs = declared_references(cfg, kind.outputs(cfg));
  if (!refs.empty()) {
    summary += ' ';
    summary += std::to_string(refs.size());
    summary += " declared reference figure(s).";
  }
  return summary;
}

nlohmann::json replay_sample(const std::string& study_path, std::size_t index, const RunOptions& options) {
  const StudyConfig cfg = load_study(study_path);
  return study_kind(cfg.kind).replay(cfg, index, options);
}

std::string run_study(const std::string& study_path, const RunOptions& options) {
  const StudyConfig cfg = load_study(study_path);
  const StudyKind& kind = study_kind(cfg.kind);
  if (!kind.streams() && (!options.resume.empty() || !options.until.empty() || sampling::Cluster::size() > 1)) {
    throw Error("--resume, --until and MPI runs are for study kinds that stream their samples; a " + cfg.kind +
                " study runs in one process in seconds to minutes (Ctrl-C still stops it cleanly)");
  }
  kind.validate(cfg);  // nothing runs until everything validates
  declared_references(cfg, kind.outputs(cfg));
  return kind.run(cfg, options);
}

}  // namespace poise::studies
