#pragma once
/// A designer's parts in a model file: the gimbal rotor (or any assembly) as meshes from CAD.
///
///   [[geometry.part]]
///   name = "rotor_disk"
///   mesh = "meshes/rotor_disk.stl"      # STL (binary or ASCII) or OBJ, relative to the model file
///   unit = "mm"                          # mm | cm | m | in: the length unit of the export
///   density = "2700 kg/m^3"
///   translation = ["0 mm", "0 mm", "0 mm"]      # optional: part frame origin in the assembly
///   rotation = ["0 deg", "0 deg", "0 deg"]      # optional: about the assembly's x, then y, then z
///   [geometry.part.tolerances.density]          # each tolerance optional (tolerance_spec.h)
///   tolerance = "15 kg/m^3"  ...
///   [geometry.part.tolerances.position]         # each of x, y, z drawn alone (three draws)
///   [geometry.part.tolerances.angle]            # small rotation about x, y, z (three draws)
///   [geometry.part.tolerances.scale]            # uniform size error, a plain number (0.001)
///
/// Each mesh is loaded, checked (geometry/mesh_check.h: refused at its `mesh` key with the
/// checker's message) and integrated exactly once; a sample then moves the parts through its
/// draws in closed form (geometry/part_assembly.h).
#include <span>
#include <string>
#include <vector>

#include "engine/study_files/input_column.h"
#include "engine/study_files/tolerance_spec.h"
#include "engine/study_files/toml_reader.h"
#include "geometry/part_assembly.h"

namespace poise::engine {

struct UserPart {
  geometry::AssemblyPart part;  ///< nominal: density, placement, unit-density properties
  std::string mesh_file;        ///< as resolved (relative to the model file's folder)
  std::string unit;             ///< of the mesh file
  std::size_t triangles = 0, shells = 0;
  /// Absent tolerances are fixed at zero and add no input column.
  ToleranceSpec density, position, angle, scale;
  bool has_density = false, has_position = false, has_angle = false, has_scale = false;
};

struct UserParts {
  std::vector<UserPart> parts;
  std::vector<std::string> warnings;  ///< a size that suggests the wrong unit (mesh_check.h)
};

/// Metres per mesh length unit: "mm", "cm", "m" or "in" (a model file's `unit` choices).
double mesh_unit_size(const std::string& unit);

/// Reads every [[<table>.part]] of `table` (the [geometry] table of a model file); mesh paths
/// relative to `base_dir`. Errors are recorded in the reader's context (finish() throws them).
UserParts read_user_parts(TomlReader& table, const std::string& base_dir);

/// A file of kind "user_parts": [model] (kind, name, title, source) and [[geometry.part]].
/// Throws ValidationError.
UserParts load_user_parts_file(const std::string& path);

/// Maps design points to the parts' deviations and the assembly as built. Immutable,
/// thread-safe. Columns per part with a tolerance: <name>_ddensity_kg_m3, <name>_dx_mm,
/// _dy_mm, _dz_mm, <name>_rx_deg, _ry_deg, _rz_deg, <name>_scale_ppm.
class UserPartsSampler {
 public:
  explicit UserPartsSampler(UserParts parts);
  std::size_t dimension() const { return columns_.size(); }
  const std::vector<InputColumn>& columns() const { return columns_; }
  const std::vector<geometry::AssemblyPart>& nominal() const { return nominal_; }
  /// u: design point (size dimension()); values: drawn inputs in display units (same size).
  std::vector<geometry::PartDeviation> draw(std::span<const double> u, std::span<double> values) const;
  /// The assembly as built for these draws (mass, centre of mass, inertia about it; SI).
  geometry::MassProperties as_built(std::span<const double> u, std::span<double> values) const;

 private:
  UserParts parts_;
  std::vector<geometry::AssemblyPart> nominal_;
  std::vector<InputColumn> columns_;
};

}  // namespace poise::engine
