#pragma once
/// The sections of a geometry_mass_properties study file (model: models/simulator_disk_*.toml):
///   [mass_properties]  rays_per_side = 200   (ray grid across each part's larger side)
///                      grid = "per_part" | "one_scene"
///                      convergence = [25, 50, 100, 200, 400]  (nominal disk, reported)
///                      export_mesh = true    (the nominal disk as STL and OBJ in the run folder)
#include <memory>
#include <vector>

#include "engine/study_files/study_config.h"

namespace poise::engine {
class TomlReader;  // engine/study_files/toml_reader.h
}  // namespace poise::engine

namespace poise::kinds::geometry_mass_properties {

struct MassPropertiesSections : engine::KindSectionsOf<MassPropertiesSections> {
  int rays_per_side = 200;
  bool per_part = true;
  std::vector<int> convergence{25, 50, 100, 200, 400};
  bool export_mesh = true;
};

/// Reads [mass_properties] (errors go to the reader's context).
std::unique_ptr<engine::KindSections> read_mass_properties_sections(engine::TomlReader& root);

inline const MassPropertiesSections& mass_properties_sections(const engine::StudyConfig& cfg) {
  return engine::sections_of<MassPropertiesSections>(cfg);
}

}  // namespace poise::kinds::geometry_mass_properties
