#pragma once
/// A study kind is one module behind this interface: a folder src/kinds/<kind>/ and one line
/// in the table of src/kinds/registry.cc.in (the build writes registry.cc from it). The engine
/// (study-file reading, run plan, sample driver, resume, convergence, provenance, result
/// writing, report assembly) reaches a kind only through this interface and names none.
///
/// What a kind does:
///   - reads and validates its own sections of a study file (read_sections, validate),
///   - computes and replays samples (run, replay; procedure-like kinds get both from
///     ProcedureKind, engine/kind_interface/procedure_kind.h, by making one ProcedureStudy),
///   - names its per-sample outputs with their units (outputs),
///   - contributes its report sections (through the ProcedureStudy or its own runner),
///   - optionally evaluates in memory for `poise optimize` (evaluate).
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/kind_interface/input_evaluation.h"
#include "engine/kind_interface/measured_effects.h"
#include "engine/kind_interface/output_spec.h"
#include "engine/kind_interface/study_evaluation.h"
#include "engine/run/study_runner.h"
#include "engine/study_files/study_config.h"
#include "engine/study_files/toml_reader.h"
#include "estimators/residual_diagnosis.h"
#include "estimators/torque_table.h"

namespace poise::engine {

class StudyKind {
 public:
  virtual ~StudyKind() = default;
  /// The value of [study] kind this module runs ("seeker_los").
  virtual std::string name() const = 0;
  /// What the kind simulates, in a sentence or two (for `poise --help` and `poise keys`).
  virtual std::string summary() const = 0;
  /// Reads the kind's own sections of a study file; errors are recorded on `root`.
  virtual std::unique_ptr<KindSections> read_sections(TomlReader& root, const StudyConfig& cfg) const = 0;
  /// Study keys an override may set (an optimizer's choice of a test plan); returns the
  /// rest (model keys). Throws ValidationError for a bad study key. Default: none.
  virtual std::map<std::string, std::string> apply_study_overrides(
      StudyConfig& cfg, const std::map<std::string, std::string>& overrides) const;
  /// Validates the study together with its model; returns a short human summary. Throws
  /// ValidationError.
  virtual std::string validate(const StudyConfig& cfg) const = 0;
  /// Per-sample outputs of this study with units (validates the model).
  virtual std::vector<OutputSpec> outputs(const StudyConfig& cfg) const = 0;
  /// The study's requirements: its [[requirement]] tables (the default) and any shorthand of
  /// the kind's own (the seeker's [requirement] los_error), in the outputs' terms.
  virtual std::vector<Requirement> requirements(const StudyConfig& cfg) const { return cfg.requirements; }
  /// Runs the study and writes its result folder; returns its path.
  virtual std::string run(const StudyConfig& cfg, const RunOptions& options) const = 0;
  /// Recomputes sample `index` alone (inputs and outputs by name).
  virtual nlohmann::json replay(const StudyConfig& cfg, std::size_t index, const RunOptions& options) const = 0;
  /// For a Monte Carlo on a model file alone (the one `poise budget` sets beside a budget):
  /// the [model] kind of the files this kind samples ("seeker_two_axis"); "" (the default):
  /// none, and the two functions below are not called.
  virtual std::string model_kind() const { return ""; }
  /// A study of this kind on `model_path` alone: the kind's default sections, plain Monte
  /// Carlo (independent samples). Default: refused (poise::Error).
  virtual StudyConfig model_study(const std::string& model_path) const;
  /// The model's sampled tolerances, dotted ("yaw.perpendicularity"), for a budget line's
  /// model_key. Default: none.
  virtual std::vector<std::string> model_tolerance_keys(const std::string& /*model_path*/) const { return {}; }
  /// One in-memory run with extra model overrides, for the optimizer (common random
  /// numbers: the same seed gives every design point the same draws). Default: refused.
  virtual McResult evaluate(const StudyConfig& cfg, const std::map<std::string, std::string>& model_overrides,
                            std::size_t samples, std::uint64_t seed, int threads) const;
  /// The kind's fast model, for an optimizer's search that is then verified on the full model
  /// (StudyConfig::fast_model): what it leaves out and how far it is known to be from the full
  /// model, in a sentence; "" (the default): the kind has none.
  virtual std::string fast_model(const StudyConfig& /*cfg*/) const { return ""; }
  /// Whether a sample draws beyond its design point (per-test draws, sensor noise). Default:
  /// no.
  virtual bool has_own_randomness(const StudyConfig& /*cfg*/) const { return false; }
  /// The study's outputs at input values a caller gives (engine/kind_interface/input_evaluation.h), on its
  /// model with `model_overrides` on top; point k of a kind with randomness of its own gets
  /// the draws of sample k of a run with `seed`. Default: refused (poise::Error saying why).
  virtual std::unique_ptr<InputEvaluator> input_evaluator(const StudyConfig& cfg,
                                                          const std::map<std::string, std::string>& model_overrides,
                                                          std::uint64_t seed) const;
  /// Whether this kind's model takes effects measured in a test table (effects_in_model).
  virtual bool takes_measured_effects() const { return false; }
  /// The effects a residual diagnosis found in a measured table (`table` gives its unit and
  /// whether it has time stamps), as keys of this study's model, and the outputs to compare
  /// (engine/kind_interface/measured_effects.h). Default: nullopt (its model takes none).
  virtual std::optional<EffectsInModel> effects_in_model(const StudyConfig& /*cfg*/,
                                                         const estimators::TorqueTable& /*table*/,
                                                         const estimators::DiagnosisResult& /*result*/) const {
    return std::nullopt;
  }
};

/// Adds a kind to the table (the registry.cc the build makes from src/kinds/registry.cc.in calls it
/// once per kind).
void register_study_kind(std::unique_ptr<StudyKind> kind);
/// The kind of that name; throws poise::Error naming the registered kinds if there is none.
const StudyKind& study_kind(const std::string& name);
/// Every registered kind, in registration order.
std::vector<const StudyKind*> study_kinds();
/// Names of the registered kinds.
std::vector<std::string> study_kind_names();

}  // namespace poise::engine
