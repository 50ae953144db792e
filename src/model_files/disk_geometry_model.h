#pragma once
/// The simulator disk as built (models/simulator_disk_*.toml): the drawing (disk, the two
/// circles of eight holes, clump weights) and the tolerances of its making, drawn per
/// Monte Carlo sample into one as-built DiskSpec:
///   tolerances.hole_position  deviation of each hole centre along x and along y (two draws
///                             per hole: a true-position error in a random direction)
///   tolerances.clump_mass     deviation of each clump weight's mass
///   tolerances.thickness      deviation of the disk's thickness
///   tolerances.wedge          face parallelism: thickness difference across the diameter
///                             (magnitude), towards a uniformly random direction
/// The disk's frame: z its axis (the gimbal axis of the test), x towards hole 0 of circle C_A.
#include <map>
#include <span>
#include <string>
#include <vector>

#include "engine/study_files/model_overrides.h"
#include "engine/study_files/tolerance_spec.h"
#include "geometry/generators.h"
#include "model_files/seeker_model.h"

namespace poise::model_files {
using engine::InputColumn;
using engine::ModelHeader;
using engine::ToleranceSpec;
using engine::ValidationError;

struct DiskGeometryModel : ModelHeader {  ///< file, name, title, source of the model file
  geometry::DiskSpec nominal;
  ToleranceSpec hole_position, clump_mass, thickness, wedge;
};

/// Loads and validates; `overrides` replace values by dotted key. Throws ValidationError.
DiskGeometryModel load_disk_geometry_model(const std::string& path,
                                           const std::map<std::string, std::string>& overrides = {});

/// Maps design points to as-built disks. Immutable, thread-safe.
class DiskSampler {
 public:
  explicit DiskSampler(DiskGeometryModel model);
  std::size_t dimension() const { return columns_.size(); }
  const std::vector<InputColumn>& columns() const { return columns_; }
  /// u: design point (size dimension()); values: drawn inputs in display units.
  geometry::DiskSpec draw(std::span<const double> u, std::span<double> values) const;
  /// The disk of input values in SI (columns()' order, display value x display_factor): what
  /// draw() returns for the values it draws.
  geometry::DiskSpec spec_of(std::span<const double> si) const;
  /// The nominal disk's inputs: every deviation zero.
  std::vector<double> nominal() const;

 private:
  DiskGeometryModel model_;
  std::vector<InputColumn> columns_;
};

}  // namespace poise::model_files
