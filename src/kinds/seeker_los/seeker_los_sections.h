#pragma once
/// The sections of a seeker_los study file (the shared ones are in engine/study_files/study_config.h):
///   [grid]         yaw_points, pitch_points (over the model's field of regard)
///   [requirement]  los_error = "1 px" (or any angle): the limit of the field figures, and a
///                  shorthand for the requirement "p99.73 of los_max_px (or los_max_arcsec)
///                  at most 1 px, at 95% confidence"; or, instead, [[requirement]] tables
///                  (engine/results/requirements.h), the first on los_max_arcsec or los_max_px
///                  giving the field figures their limit; or none (the field figures are then
///                  taken against 1 px)
///   [clearance]    output = true, yaw_points, pitch_points (optional; the nominal frames'
///                  least clearance to the housing as an output: SeekerClearanceSpec below)
///   [output]       contribution_samples = 4096 (each tolerance set to zero in turn; 0 = off)
///                  grid_values = true (the LOS error at each grid point of every sample in
///                  samples.h5; false keeps them only as long as the maps need)
///                  maps = true (each grid point's p50, p95, p99.73 and the pooled figures;
///                  false with grid_values false: nothing per grid point is made)
///                  grid_values_in_memory_mb = 256 (a run's grid values are kept in memory for
///                  its field statistics when they take at most this much, else read back
///                  from samples.h5 column by column; 0 = always read back)
#include <string>
#include <vector>

#include "engine/results/wide_columns.h"
#include "engine/study_files/study_config.h"

namespace poise::kinds::seeker_los {
using engine::KindSections;
using engine::KindSectionsOf;
using engine::kKeepColumnsBytes;
using engine::sections_of;
using engine::StudyConfig;
using engine::TomlReader;

/// [clearance] output = true: the optimizer's evaluation of the study gets one more output,
/// min_clearance_mm, the least clearance of the nominal frames to the housing over a
/// yaw_points x pitch_points grid (default 3 x 3: the field's corners, edges and centre), the
/// same for every sample of a design (seeker_clearance.h); the model needs a [geometry] section.
struct SeekerClearanceSpec {
  bool clearance_output = false;
  std::size_t clearance_yaw_points = 3, clearance_pitch_points = 3;
};

struct SeekerLosSections : KindSectionsOf<SeekerLosSections> {
  std::size_t yaw_points = 13, pitch_points = 13;
  double requirement = 0.0;  ///< as written, in its unit's SI (rad or px)
  bool requirement_in_pixels = true;
  std::string requirement_text;
  bool requirement_shorthand = true;  ///< stated as [requirement] los_error (not [[requirement]])
  /// Contribution of each tolerance: the study re-run with that tolerance set to zero
  /// (same random numbers), with this many samples; 0 switches it off.
  std::size_t contribution_samples = 4096;
  bool grid_values = true, maps = true;  ///< [output]
  /// The grid values (4 bytes each) kept in memory at most, in MiB (SeekerLosStudy::run).
  std::size_t grid_values_in_memory_mb = kKeepColumnsBytes >> 20;
  SeekerClearanceSpec clearance;  ///< [clearance]
};

/// Reads the seeker_los sections (errors recorded on `root`).
std::unique_ptr<KindSections> read_seeker_los_sections(TomlReader& root, const StudyConfig& cfg);

inline const SeekerLosSections& seeker_sections(const StudyConfig& cfg) { return sections_of<SeekerLosSections>(cfg); }

}  // namespace poise::kinds::seeker_los
