#pragma once
/// A study file (studies/*.toml): what to run, on which model, how to sample, what to
/// report. Strict like the model files: unknown keys, missing units and non-physical
/// values are refused with file, line, key, value and what was expected.
///
/// The sections every kind shares (read here):
///   [study]       name, kind (a registered study kind: `poise --help`), model (path relative
///                 to the study file), title, notes
///   [sampling]    method = "sobol" | "lhs" | "monte_carlo", samples, seed,
///                 replicate_size (optional), max_failure_share (optional, default 0.05)
///   [overrides]   "dotted.model.key" = "value"      (optional)
///   [output]      plots = true, block = 1024, contribution_samples = 0, samples_csv = true
///                 (optional; samples_csv = false leaves samples.csv out); a kind may read keys
///                 of its own there (the seeker's grid_values and maps)
///   [[reference]] figures to compare with (engine/results/references.h): name, output, statistic,
///                 value, source, role = "validation" | "calibration_target"
///   [[sweep]]     parameter = "dotted.model.key", values = [...], samples (optional; default:
///                 the run's sample count, --samples included)
///   [[requirement]] output, statistic, at_most | at_least, confidence (engine/results/requirements.h)
/// Every other section belongs to the kind and is read by its module (src/kinds/<kind>/);
/// `poise keys KIND` lists them.
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/results/requirements.h"
#include "sampling/design.h"

namespace poise::engine {

class TomlReader;  // engine/study_files/toml_reader.h

/// A kind's own sections of a study file, read by its module (StudyKind::read_sections).
struct KindSections {
  virtual ~KindSections() = default;
  virtual std::unique_ptr<KindSections> clone() const = 0;
};
/// Base of a kind's sections struct T (gives it clone()).
template <class T>
struct KindSectionsOf : KindSections {
  std::unique_ptr<KindSections> clone() const override { return std::make_unique<T>(static_cast<const T&>(*this)); }
};

/// The kind's sections held by a StudyConfig: copied deeply with it (a study's copy may
/// change its test plan without touching the original).
class KindSectionsPtr {
 public:
  KindSectionsPtr() = default;
  template <class T>
  KindSectionsPtr(std::unique_ptr<T> p) : p_(std::move(p)) {}  // NOLINT: implicit by design
  KindSectionsPtr(const KindSectionsPtr& o) : p_(o.p_ ? o.p_->clone() : nullptr) {}
  KindSectionsPtr(KindSectionsPtr&&) noexcept = default;
  KindSectionsPtr& operator=(const KindSectionsPtr& o) {
    if (this != &o) p_ = o.p_ ? o.p_->clone() : nullptr;
    return *this;
  }
  KindSectionsPtr& operator=(KindSectionsPtr&&) noexcept = default;
  KindSections* get() const { return p_.get(); }
  explicit operator bool() const { return p_ != nullptr; }

 private:
  std::unique_ptr<KindSections> p_;
};

/// A reference figure declared in a study or model file ([[reference]]): a paper's or a
/// customer's figure to set beside the study's own. Only declared figures are compared.
struct ReferenceFigure {
  std::string name;        ///< what the figure is ("C_A loading tests: RMSE of MT_s")
  std::string output;      ///< the study output it compares with
  std::string statistic;   ///< "sample" (one realisation: where it falls in the simulated
                           ///< distribution) or mean | std | p50 | p95 | p99_73 | max
  std::string value_text;  ///< as written ("0.78 mN*m")
  double value_si = 0.0;
  std::string source;
  std::string role;                 ///< "validation" | "calibration_target"
  std::string follows_from;         ///< calibration target: what was calibrated to it
  double tolerance_relative = 0.0;  ///< validation: also agrees within this share (0 = interval only)
  std::string file;                 ///< declared in (study or model file)
  int line = 0;
};

/// A [[sweep]]: the study re-run at each value of one model key with the same seed (common
/// random numbers), so that differences between values are the design's.
struct SweepSpec {
  std::string parameter;            ///< dotted model key ("yaw.bearing_span")
  std::vector<std::string> values;  ///< as written, with units
  std::size_t samples = 0;          ///< per value; 0 (not given): the run's sample count
  int line = 0;
};

/// The samples of each value of a sweep in a run of `run_samples` samples.
inline std::size_t sweep_samples(const SweepSpec& sw, std::size_t run_samples) {
  return sw.samples > 0 ? sw.samples : run_samples;
}

struct StudyConfig {
  std::string file;  ///< path of the study file
  std::string name, kind, title, notes;
  std::string model_path;  ///< resolved against the study file's folder
  sampling::SamplingMethod method = sampling::SamplingMethod::kSobol;
  std::size_t samples = 0;
  std::uint64_t seed = 0;
  /// [sampling] replicate_size: lhs and sobol in independent randomized replicates of this
  /// many points (sobol: a power of two), so that intervals come from their spread and
  /// --until can grow the run replicate by replicate; samples must be a multiple. 0 = off.
  std::size_t replicate_size = 0;
  /// [sampling] max_failure_share: the run stops with an error once more than this share
  /// of its samples has failed (default 0.05).
  double max_failure_share = 0.05;
  /// Not a file key: set by `poise sensitivity`, the base rows of the Saltelli layout
  /// (sampling/design.h) and whether the within-sample randomness is a group of its own.
  std::size_t saltelli_base = 0;
  bool saltelli_noise_group = false;
  std::size_t saltelli_noise_sources = 1;  ///< its sources, each a group (ProcedureStudy::randomness_sources)
  /// Closed groups of several design dimensions (one per model tolerance drawn in more than
  /// one column), laid out after the per-dimension groups; set by a kind before plan_run.
  std::vector<std::vector<std::size_t>> saltelli_groups;
  /// Not a file key: set by the optimizer's search (`search_model = "fast"`), the kind's fast
  /// model (StudyKind::fast_model) instead of its full one.
  bool fast_model = false;
  std::map<std::string, std::string> overrides;
  bool plots = true;
  std::size_t block = 1024;
  /// [output] contribution_samples: each model tolerance set to zero in turn, with this many
  /// samples (engine/run/procedure_contributions.h); 0 = off (the seeker reads its own default).
  std::size_t contribution_samples = 0;
  /// [output] samples_csv: every sample's inputs and outputs in samples.csv (and, for a kind
  /// without a field, as named columns in samples.h5); false leaves them out and with them
  /// --resume, which restarts from samples.csv.
  bool samples_csv = true;
  std::vector<ReferenceFigure> references;  ///< the study file's [[reference]] tables
  /// The study file's [[requirement]] tables (engine/results/requirements.h), and a kind's shorthand
  /// for one (the seeker's [requirement] los_error) added by its section reader.
  std::vector<Requirement> requirements;
  std::vector<SweepSpec> sweeps;  ///< the study file's [[sweep]] tables

  /// The kind's own sections (its module's struct).
  KindSectionsPtr sections;
};

[[noreturn]] void throw_wrong_sections(const StudyConfig& cfg);

/// The kind's sections of a study as its module's struct T; throws poise::Error if the
/// study is of another kind.
template <class T>
const T& sections_of(const StudyConfig& cfg) {
  const T* t = dynamic_cast<const T*>(cfg.sections.get());
  if (!t) throw_wrong_sections(cfg);
  return *t;
}
template <class T>
T& mutable_sections_of(StudyConfig& cfg) {
  T* t = dynamic_cast<T*>(cfg.sections.get());
  if (!t) throw_wrong_sections(cfg);
  return *t;
}
/// Whether a study's samples are independent draws or randomized replicates (monte_carlo, or
/// any design with replicate_size): the one-sided bounds of its statistics then hold.
inline bool independent_samples(const StudyConfig& cfg) {
  return cfg.method == sampling::SamplingMethod::kMonteCarlo || cfg.replicate_size > 0;
}
/// The design of a study's samples: method, seed, replicates and Saltelli layout as configured.
sampling::Design make_design(const StudyConfig& cfg, std::uint64_t seed, std::size_t samples, std::size_t dimension);

/// Loads and validates a study file (not its model): the shared sections here, the kind's
/// through its module. Throws ValidationError.
StudyConfig load_study(const std::string& path);

/// Splits the kind's study keys off a set of overrides and applies them to `cfg` (e.g. a
/// gimbal study's "group.positions": an optimizer's choice of test plan); returns the rest
/// (model keys). Throws ValidationError for a bad study key.
std::map<std::string, std::string> apply_study_overrides(StudyConfig& cfg,
                                                         const std::map<std::string, std::string>& overrides);

}  // namespace poise::engine
