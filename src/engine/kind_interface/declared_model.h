#pragma once
/// A model file that declares its own parameters and outputs, for the kinds whose mechanism is
/// the user's (formulas, an external program, a Python function), not compiled in:
///
///     [model]
///     kind = "..."
///     name = "bearing stack axial gap"
///
///     [parameters]                 # each value with its unit: its dimension and the unit
///     shaft = "208 mm"             # samples.csv and the user's code see it in; a plain
///     count = 3                    # number has no unit. The file's order is the inputs' order.
///
///     [tolerances.shaft]           # as for every kind (engine/study_files/tolerance_spec.h)
///     ...
///
///     [[output]]                   # one or more
///     name = "gap"
///     unit = "mm"
///     description = "axial play of the stack"
///
/// A name is a word of letters, digits and _ that starts with a letter (it names a column of
/// samples.csv, a variable of a formula, a key of the user's program).
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "engine/kind_interface/closed_form_study.h"

namespace poise::engine {

/// What is wrong with `name` for a parameter or output ("" if nothing): not a word, taken by
/// the language (`reserved`, may be empty), or declared before (in `taken`).
std::string declared_name_fault(const std::string& name, const std::map<std::string, units::Dimension>& taken,
                                const std::function<bool(const std::string&)>& reserved);

/// The [parameters] of the model file in the file's order, each with the dimension and unit of
/// its value; adds their names to `taken`. Faults go to ctx (file, line, column). In `poise keys`
/// (a schema read) one stand-in, NAME, asks for the table's keys.
std::vector<ClosedFormParameter> declared_parameters(TomlReader& root, const toml::table& doc,
                                                     std::map<std::string, units::Dimension>& taken,
                                                     const std::function<bool(const std::string&)>& reserved);

/// The [[output]] tables with name, unit and description (and `more(table)` for a kind's own
/// keys of each); at least one. Faults on root's context.
std::vector<OutputSpec> declared_outputs(TomlReader& root, std::map<std::string, units::Dimension>& taken,
                                         const std::function<bool(const std::string&)>& reserved);

/// A declared model as read: its declaration (parameters and outputs) and its parameters'
/// values and tolerances.
struct DeclaredModel {
  ClosedFormDeclaration declaration;
  ClosedFormModel model;
};

/// Reads the model file at `path` (overrides on it) of [model] kind `kind`: its parameters,
/// tolerances and [[output]] tables, and with `model_keys` the kind's own keys of [model]
/// (read before the file is finished, so an unknown key is still refused). Throws
/// ValidationError.
DeclaredModel read_declared_model(const std::string& path, const std::map<std::string, std::string>& overrides,
                                  const std::string& kind, const std::function<void(TomlReader& model)>& model_keys);

/// A function that computes a declared model in the units its file writes: the parameters in
/// the units their values are written in, the outputs in their declared units (an external
/// program, a Python function). It converts from and to SI for the closed-form study.
class DeclaredUnitsFunction : public ClosedFormFunction {
 public:
  explicit DeclaredUnitsFunction(const ClosedFormDeclaration& declaration);
  /// One row, through compute_batch.
  void compute(std::span<const double> parameters, std::span<double> outputs) override;
  void compute_batch(std::span<const std::size_t> ids, std::span<const double> parameters, std::span<double> outputs,
                     std::vector<std::string>& failures) override;

 protected:
  /// Rows of `inputs` (input_names(), written units, row-major) to `outputs` (output_names(),
  /// declared units); a row without an answer gets its reason in failures (n "" on entry).
  virtual void evaluate(std::span<const std::size_t> ids, const std::vector<double>& inputs, std::span<double> outputs,
                        std::vector<std::string>& failures) = 0;
  const std::vector<std::string>& input_names() const { return inputs_; }
  const std::vector<std::string>& output_names() const { return outputs_; }

 private:
  std::vector<std::string> inputs_, outputs_;
  std::vector<double> in_factor_, out_factor_;  ///< SI per written unit
};

}  // namespace poise::engine
