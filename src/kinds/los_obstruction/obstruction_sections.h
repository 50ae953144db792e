#pragma once
/// The sections of a los_obstruction study file (model: a seeker model with a [geometry]
/// section, model_files/seeker_geometry.h):
///   [grid]             yaw_points, pitch_points (over the model's field of regard)
///   [beam]             rays = 1024 (over the clear aperture)
///   [clearance]        per_sample = true (clearance at every grid point of every sample;
///                      false: the nominal design only), warn_below = "0.5 mm"
#include <cstddef>
#include <memory>

#include "engine/study_files/study_config.h"

namespace poise::engine {
class TomlReader;  // engine/study_files/toml_reader.h
}  // namespace poise::engine

namespace poise::kinds::los_obstruction {

struct ObstructionSections : engine::KindSectionsOf<ObstructionSections> {
  std::size_t yaw_points = 7, pitch_points = 7;
  int beam_rays = 1024;
  bool clearance_per_sample = true;
  double clearance_warn = 0.5e-3;  ///< m
};

/// Reads [grid], [beam] and [clearance] (errors go to the reader's context).
std::unique_ptr<engine::KindSections> read_obstruction_sections(engine::TomlReader& root);

inline const ObstructionSections& obstruction_sections(const engine::StudyConfig& cfg) {
  return engine::sections_of<ObstructionSections>(cfg);
}

}  // namespace poise::kinds::los_obstruction
