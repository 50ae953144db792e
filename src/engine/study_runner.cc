#include "engine/study_runner.h"

#include "engine/checked_file.h"
#include "engine/references.h"
#include "engine/run_plan.h"
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
    throw UsageError("--resume, --until and MPI runs are for study kinds that stream their samples; a " + cfg.kind +
                " study runs in one process in seconds to minutes (Ctrl-C still stops it cleanly)");
  }
  kind.validate(cfg);  // nothing runs until everything validates
  declared_references(cfg, kind.outputs(cfg));
  try {
    return kind.run(cfg, options);
  } catch (const WriteError& e) {
    // A full disk or another refused write: the run stopped at the first one. The folder
    // says "failed" (never "complete"); the samples on disk stay for a resume.
    if (!sampling::Cluster::root()) throw;
    const std::string dir = record_write_failure(e.path(), e.what());
    std::string message = std::string(e.what()) + ". The run stopped";
    if (!dir.empty()) {
      message += "; " + dir + " is marked \"failed\"";
      if (kind.streams()) message += ", and `poise run --resume " + dir + "` continues it once the cause is fixed";
    }
    throw Error(message);
  }
}

}  // namespace poise::studies
