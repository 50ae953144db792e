#pragma once
/// The study of every closed-form model (a function from toleranced parameters to outputs,
/// engine/kind_interface/closed_form_kind.h): its model file's [parameters] and [tolerances]
/// read against a declaration, and one study that draws the parameters of each sample and
/// calls a function of the model, one per thread. Kinds with a compiled formula (a C++
/// ClosedFormKind) and kinds whose formulas come with the model file (kinds/formula) share it.
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "engine/kind_interface/closed_form_kind.h"
#include "engine/kind_interface/procedure_study.h"
#include "engine/study_files/model_overrides.h"
#include "engine/study_files/tolerance_spec.h"

namespace poise::engine {

/// The study file's sections of a closed-form kind: none beyond the shared ones.
struct ClosedFormSections : KindSectionsOf<ClosedFormSections> {};

/// One thread's means of computing a sample (it may keep scratch state between samples).
class ClosedFormFunction {
 public:
  virtual ~ClosedFormFunction() = default;
  /// The outputs (SI, declared order) from the parameters (SI, declared order). Throws
  /// poise::Error for a draw without a physical answer: the sample fails with that reason.
  virtual void compute(std::span<const double> parameters, std::span<double> outputs) = 0;
  /// Rows [0, ids.size()) at once, `parameters` and `outputs` row-major (SI; one row per id,
  /// the sample or point it is). A row without a physical answer gets its reason in
  /// failures[row] (the others ""), its outputs left as they are. Default: compute() row by row.
  virtual void compute_batch(std::span<const std::size_t> ids, std::span<const double> parameters,
                             std::span<double> outputs, std::vector<std::string>& failures);
};
/// Makes one function per thread.
using ClosedFormFunctions = std::function<std::unique_ptr<ClosedFormFunction>()>;

/// A closed-form model file as read: header, each parameter's value and, where toleranced,
/// how it is drawn.
struct ClosedFormModel {
  ModelHeader header;
  std::vector<double> values;  ///< SI, declared order
  struct Drawn {
    std::size_t parameter = 0;
    ToleranceSpec spec;
    bool range = false;  ///< min/max: the value itself; else a deviation from the value
  };
  std::vector<Drawn> drawn;
};

/// Reads the model's [model] header, [parameters] (every declared one, in its dimension) and
/// [tolerances] (errors on root's context; the caller finishes the file).
ClosedFormModel read_closed_form_model(const ClosedFormDeclaration& declaration, TomlReader& root);

/// The study of a closed-form model over `samples` samples with `seed`.
/// `batch` > 1: the function is called with batches of that many samples (an external
/// program, a Python function), each thread's samples in a batch of their own.
std::unique_ptr<ProcedureStudy> make_closed_form_study(const StudyConfig& cfg, ClosedFormDeclaration declaration,
                                                       ClosedFormModel model, ClosedFormFunctions functions,
                                                       std::size_t samples, std::uint64_t seed, std::size_t batch = 1);

/// validate()'s check of a closed-form study (no sweep of a parameter drawn from a range) and
/// its one-line summary. Throws ValidationError.
std::string validate_closed_form(const StudyConfig& cfg, const ClosedFormDeclaration& declaration,
                                 const ClosedFormModel& model);

}  // namespace poise::engine
