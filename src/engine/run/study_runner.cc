#include "engine/run/study_runner.h"
#include "engine/study_files/model_overrides.h"

#include <filesystem>
#include <fstream>

#include "engine/kind_interface/study_kind.h"
#include "engine/results/checked_file.h"
#include "engine/results/references.h"
#include "engine/results/requirements.h"
#include "engine/run/run_plan.h"
#include "sampling/distributed.h"

namespace poise::engine {

namespace {

// Each sweep value is a model the kind accepts: the study validated with it as an override.
void check_sweeps(const StudyConfig& cfg, const StudyKind& kind) {
  std::vector<InputError> errors;
  for (const auto& sw : cfg.sweeps) {
    for (const auto& v : sw.values) {
      try {
        StudyConfig c = cfg;
        auto overrides = c.overrides;
        overrides[sw.parameter] = v;
        c.overrides = apply_study_overrides(c, overrides);
        kind.validate(c);
      } catch (const ValidationError& e) {
        bool unknown_key = false;
        for (const auto& err : e.errors()) {
          const std::string what = err.what();
          if (what.find(kUnknownModelKey) != std::string::npos) {
            // Not the value: the key. Said once for the sweep, not once per value.
            const auto near = what.find("; did you mean");
            errors.emplace_back(SourceLocation{cfg.file, sw.line, 0}, "sweep.parameter", "\"" + sw.parameter + "\"",
                                "a key of the model file " + cfg.model_path +
                                    (near == std::string::npos ? std::string() : what.substr(near)));
            unknown_key = true;
            break;
          }
          errors.emplace_back(SourceLocation{cfg.file, sw.line, 0}, "sweep " + sw.parameter, "\"" + v + "\"",
                              std::string("a value the model accepts: ") + what);
        }
        if (unknown_key) break;
      }
    }
  }
  if (!errors.empty()) throw ValidationError(errors);
}

// What checking a study found: the kind's summary line, its outputs and requirements.
struct CheckedStudy {
  std::string summary;
  std::vector<OutputSpec> outputs;
  std::vector<Requirement> requirements;
};

// Everything a run needs valid before it starts: the study with its model, the declared
// references, the requirements and every sweep value.
CheckedStudy check_study(const StudyConfig& cfg, const StudyKind& kind) {
  CheckedStudy c{kind.validate(cfg), kind.outputs(cfg), kind.requirements(cfg)};
  const auto refs = declared_references(cfg, c.outputs);
  check_requirements(c.requirements, c.outputs);
  check_sweeps(cfg, kind);
  if (!refs.empty()) c.summary.append(" ").append(std::to_string(refs.size())).append(" declared reference figure(s).");
  return c;
}

}  // namespace

std::string validate_study(const std::string& study_path) {
  const StudyConfig cfg = load_study(study_path);
  const CheckedStudy c = check_study(cfg, study_kind(cfg.kind));
  std::string summary = c.summary;
  if (!c.requirements.empty())
    summary.append(" ").append(std::to_string(c.requirements.size())).append(" requirement(s).");
  // What a requirement, a reference or a sweep's figure may name: each output with its unit.
  summary.append("\nOutputs per sample (name [unit]: what it is):");
  for (const auto& o : c.outputs) {
    summary.append("\n  ").append(o.name).append(" [").append(o.unit.empty() ? "1" : o.unit).append("]");
    if (!o.description.empty()) summary.append(": ").append(o.description);
  }
  return summary;
}

nlohmann::json replay_sample(const std::string& study_path, std::size_t index, const RunOptions& options) {
  const StudyConfig cfg = load_study(study_path);
  return study_kind(cfg.kind).replay(cfg, index, options);
}

std::string run_study(const std::string& study_path, const RunOptions& options) {
  StudyConfig cfg = load_study(study_path);
  if (!options.overrides.empty()) {
    auto overrides = cfg.overrides;
    for (const auto& [key, value] : options.overrides) overrides[key] = value;
    cfg.overrides = apply_study_overrides(cfg, overrides);
  }
  const StudyKind& kind = study_kind(cfg.kind);
  const CheckedStudy checked = check_study(cfg, kind);  // nothing runs until everything validates
  if (options.require && checked.requirements.empty()) {
    throw UsageError("--require: " + cfg.file +
                     " states no requirement; add a [[requirement]] table (output, "
                     "statistic, at_most or at_least, confidence) or leave --require out");
  }
  try {
    return kind.run(cfg, options);
  } catch (const WriteError& e) {
    // A full disk or another refused write: the run stopped at the first one. The folder
    // says "failed" (never "complete"); the samples on disk stay for a resume.
    if (!sampling::Cluster::root()) throw;
    const std::string dir = record_write_failure(e.path(), e.what());
    std::string message = std::string(e.what()) + ". The run stopped";
    if (!dir.empty()) {
      message += "; " + dir + " is marked \"failed\", and `poise run --resume " + dir +
                 "` continues it once the cause is fixed";
    }
    throw Error(message);
  }
}

RunAnswer run_answer(const std::string& dir) {
  RunAnswer a;
  std::ifstream in(std::filesystem::path(dir) / "summary.json");
  if (!in) return a;
  const nlohmann::json s = nlohmann::json::parse(in, nullptr, false);
  if (s.is_discarded() || !s.is_object()) return a;
  a.answer = s.value("answer", "");
  a.met = requirements_met(s);
  return a;
}

}  // namespace poise::engine
