#pragma once
/// A per-sample output (and input) a study kind declares once: its samples.csv column, its
/// unit and what it is. Every table, axis, summary.json entry, HDF5 column and Python array
/// takes its unit and meaning from here, never from a suffix of the name.
#include <span>
#include <string>
#include <vector>

#include "core/units.h"

namespace poise::engine {

struct OutputSpec {
  std::string name;         ///< samples.csv column ("g_rmse_torque_mNm")
  std::string unit;         ///< display unit of its values ("mN*m"; "1" or "" for a pure number)
  std::string description;  ///< one line: what it is
};

/// A per-sample input a study kind declares once, as it declares its outputs: its samples.csv
/// column, the display unit of its values, what it is, and the model's tolerance it is drawn
/// from. samples.h5, summary.json and Python take an input's unit from here, never from a
/// suffix of its name.
struct InputSpec {
  std::string name;         ///< samples.csv column ("yaw_radial_runout_A_um")
  std::string unit;         ///< display unit of its values ("um"; "1" for a pure number)
  std::string description;  ///< one line: what it is ("" where the tolerance key says it)
  std::string tolerance;    ///< the model's tolerance key ("tolerances.kt_drift"; "" for a derived column)
};

/// The names of a list of inputs, in order.
inline std::vector<std::string> input_names_of(const std::vector<InputSpec>& inputs) {
  std::vector<std::string> names;
  names.reserve(inputs.size());
  for (const auto& i : inputs) names.push_back(i.name);
  return names;
}

/// An output in a kind's constant table: {name (or a suffix of it), unit, description}.
struct OutputDeclaration {
  const char* name;
  const char* unit;
  const char* description;
};

/// Appends each declared output as prefix + name, its description after `what` (e.g.
/// "group g: "), to `out`.
inline void append_outputs(std::vector<OutputSpec>& out, const std::string& prefix,
                           std::span<const OutputDeclaration> declared, const std::string& what = "") {
  for (const auto& d : declared) out.push_back({prefix + d.name, d.unit, what + d.description});
}

/// One of a display unit in SI with its dimension ("" and "1": dimensionless); throws
/// poise::Error for a unit the parser does not know.
inline units::Quantity unit_quantity(const std::string& unit) {
  if (unit.empty() || unit == "1") return {1.0, units::kDimensionless};
  return units::parse_quantity("1 " + unit);
}

/// The unit of the output named `name` ("" where there is none of that name).
inline std::string output_unit_of(const std::vector<OutputSpec>& outputs, const std::string& name) {
  for (const auto& o : outputs) {
    if (o.name == name) return o.unit;
  }
  return "";
}

/// The names of a list of outputs, in order.
inline std::vector<std::string> output_names_of(const std::vector<OutputSpec>& outputs) {
  std::vector<std::string> names;
  names.reserve(outputs.size());
  for (const auto& o : outputs) names.push_back(o.name);
  return names;
}

}  // namespace poise::engine
