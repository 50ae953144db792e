#pragma once
/// Sections of the two geometry study kinds (read into StudyConfig::geometry):
///
/// kind = "geometry_mass_properties" (model: models/simulator_disk_*.toml)
///   [mass_properties]  rays_per_side = 200   (ray grid across each part's larger side)
///                      grid = "per_part" | "one_scene"
///                      convergence = [25, 50, 100, 200, 400]  (nominal disk, reported)
///                      export_mesh = true    (the nominal disk as STL and OBJ in the run folder)
/// kind = "los_obstruction" (model: a seeker model with a [geometry] section)
///   [grid]             yaw_points, pitch_points (over the model's field of regard)
///   [beam]             rays = 1024 (over the clear aperture)
///   [clearance]        per_sample = true (clearance at every grid point of every sample;
///                      false: the nominal design only), warn_below = "0.5 mm"
/// kind = "seeker_los" (optional; the model needs a [geometry] section)
///   [clearance]        output = true: the optimizer's evaluation of the study gets one more
///                      output, min_clearance_mm, the least clearance of the nominal frames to the
///                      housing over a yaw_points x pitch_points grid (default 3 x 3: the field's
///                      corners, edges and centre), the same for every sample of a design: a
///                      [[constraint]] of a bearing-span sizing can use it (kinds/seeker_los/seeker_clearance.h).
#include <cstdint>
#include <string>
#include <vector>

#include "engine/study_files/study_config.h"

namespace poise::engine {
class TomlReader;  // engine/study_files/toml_reader.h
}  // namespace poise::engine

namespace poise::geometry_studies {
using engine::KindSectionsOf;
using engine::sections_of;
using engine::StudyConfig;
using engine::TomlReader;

struct GeometryStudySpec {
  // geometry_mass_properties
  int rays_per_side = 200;
  bool per_part = true;
  std::vector<int> convergence{25, 50, 100, 200, 400};
  bool export_mesh = true;
  // los_obstruction
  std::size_t yaw_points = 7, pitch_points = 7;
  int beam_rays = 1024;
  bool clearance_per_sample = true;
  double clearance_warn = 0.5e-3;  ///< m
  // seeker_los
  bool clearance_output = false;
  std::size_t clearance_yaw_points = 3, clearance_pitch_points = 3;
};

/// Reads the sections of `kind` (errors go to the reader's context).
void read_geometry_study(TomlReader& root, const std::string& kind, GeometryStudySpec& spec);

/// The sections of the geometry kinds (and of seeker_los's [clearance]) as a study's own.
struct GeometrySections : KindSectionsOf<GeometrySections> {
  GeometryStudySpec geometry;
};
inline const GeometrySections& geometry_sections(const StudyConfig& cfg) { return sections_of<GeometrySections>(cfg); }

}  // namespace poise::geometry_studies
