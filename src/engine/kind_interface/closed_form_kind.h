#pragma once
/// A closed-form study kind: a function from a handful of toleranced parameters to outputs,
/// with no solver and no randomness of its own (a formula of the field: a shaft's sag, a
/// lever's tilt). The kind declares its parameters and outputs and computes one sample; the
/// engine does the rest as for every kind (model file, sampling, samples.csv and samples.h5,
/// statistics, requirements and their answer, sweeps, sensitivity, references, report).
///
/// The kind's model file:
///
///     [model]
///     kind = "<the kind's name>"
///     name = "my shaft"
///     source = "drawing 123-4, rev B"
///
///     [parameters]                 # every declared parameter, with its unit
///     span = "60 mm"
///
///     [tolerances.span]            # optional, for any parameter (engine/study_files/tolerance_spec.h)
///     tolerance = "0.05 mm"        # a deviation from the value above ...
///     distribution = "normal"
///     tolerance_is = "3sigma"
///     source = "ISO 2768-f"
///     # ... or min = "59.9 mm", max = "60.1 mm": the parameter's range itself
///
/// Each toleranced parameter is one design dimension and one input column of samples.csv
/// (`span_mm`: its drawn value in the declared display unit). A study file of the kind needs
/// only the shared sections (engine/study_files/study_config.h); `[overrides]` and `[[sweep]]` take
/// "parameters.<name>" keys.
///
/// Writing one: derive from ClosedFormKind, give the constructor its declaration, and
/// override compute() (SI in, SI out; throw poise::Error for a draw that has no physical
/// answer: the sample fails with that reason and the run goes on). See src/kinds/shaft_sag/.
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/units.h"
#include "engine/kind_interface/output_spec.h"
#include "engine/kind_interface/procedure_kind.h"

namespace poise::engine {

/// A parameter of a closed-form model: its key under [parameters], its dimension, the unit
/// reports and samples.csv show it in, and what it is.
struct ClosedFormParameter {
  std::string name;
  units::Dimension dimension;
  std::string display_unit;
  std::string description;
};

/// What a closed-form kind declares once.
struct ClosedFormDeclaration {
  std::string name;     ///< [study] kind and [model] kind
  std::string summary;  ///< for `poise --help` and `poise keys`
  std::vector<ClosedFormParameter> parameters;
  std::vector<OutputSpec> outputs;  ///< compute() returns them in SI, in this order
  /// How the outputs are computed, for the report: (what, formula) rows; empty for a kind
  /// whose formula is its C++ (its header states it).
  std::vector<std::pair<std::string, std::string>> formulas;
};

class ClosedFormKind : public ProcedureKind {
 public:
  explicit ClosedFormKind(ClosedFormDeclaration declaration);

  /// One sample's outputs (SI, in declared order) from its parameters (SI, declared order).
  /// Throws poise::Error for a draw without a physical answer.
  virtual std::vector<double> compute(std::span<const double> parameters) const = 0;

  const ClosedFormDeclaration& declaration() const { return declaration_; }
  std::string name() const override { return declaration_.name; }
  std::string summary() const override { return declaration_.summary; }
  std::unique_ptr<KindSections> read_sections(TomlReader& root, const StudyConfig& cfg) const override;
  std::string validate(const StudyConfig& cfg) const override;
  std::unique_ptr<ProcedureStudy> make_study(const StudyConfig& cfg,
                                             const std::map<std::string, std::string>& model_overrides,
                                             std::size_t samples, std::uint64_t seed) const override;

 private:
  ClosedFormDeclaration declaration_;
};

}  // namespace poise::engine
