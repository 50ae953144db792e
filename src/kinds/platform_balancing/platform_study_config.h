#pragma once
/// The [platform] section of a study of kind "platform_balancing"
/// (studies/platform_balancing_sequence.toml):
///   [platform]
///   orders = ["inner,middle,outer", "outer,middle,inner", ...]  # the first is the reference
///   positions = 36                      # turntable positions of each axis test
///   outer_min, outer_max, outer_points  # grid of gimbal angles for the residual torque and
///   middle_min, middle_max, middle_points  #   the LOS error (angles, inclusive)
///   inner_min, inner_max, inner_points
///   acceleration_x, _y, _z              # stated carrier acceleration (base frame) for the
///                                       #   residual torque beside gravity
///   [platform.profile]   duration, time_step, manoeuvre_x/_y/_z, onset, rise_time
///   [[platform.profile.vibration]]  amplitude_x/_y/_z, frequency
///   [platform.shafting]  study = "los_seeker_wang2011.toml" (a study of any kind, path
///                        relative to this file), samples, output = "los_max_arcsec" (its
///                        output in an angle unit: each unit's shafting LOS error) and
///                        pixel_output = "los_max_px" (the same error in px, which gives the
///                        pixel's angle): the shafting LOS line of the combined budget
///                        (optional; without it the budget has no shafting line)
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "engine/study_files/study_config.h"

namespace poise::engine {
class TomlReader;  // engine/study_files/toml_reader.h
}  // namespace poise::engine

namespace poise::kinds::platform_balancing {
using engine::KindSections;
using engine::KindSectionsOf;
using engine::sections_of;
using engine::StudyConfig;
using engine::TomlReader;

struct PlatformVibration {
  std::array<double, 3> amplitude{};  ///< m/s^2, base frame
  double frequency = 0.0;             ///< Hz
};

struct PlatformStudySection {
  std::vector<std::array<int, 3>> orders;  ///< axis indices (0 inner, 1 middle, 2 outer)
  std::vector<std::string> order_labels;   ///< "imo", "omi", ... (output prefixes)
  std::vector<std::string> order_texts;    ///< as written
  std::size_t positions = 36;
  double outer_min = 0, outer_max = 0, middle_min = 0, middle_max = 0, inner_min = 0, inner_max = 0;  ///< rad
  std::size_t outer_points = 1, middle_points = 1, inner_points = 1;
  std::array<double, 3> acceleration{};                                   ///< m/s^2, base frame
  double duration = 1.0, time_step = 1e-3, onset = 0.0, rise_time = 0.0;  ///< s
  std::array<double, 3> manoeuvre{};                                      ///< m/s^2, base frame
  std::vector<PlatformVibration> vibration;
  std::string shafting_study;  ///< resolved path, "" = none
  std::size_t shafting_samples = 4096;
  std::string shafting_output = "los_max_arcsec", shafting_pixel_output = "los_max_px";
};

/// Reads [platform] of a study file at `study_path` (errors recorded in the reader).
void read_platform_section(TomlReader& root, const std::string& study_path, PlatformStudySection& out);

struct PlatformSections : KindSectionsOf<PlatformSections> {
  PlatformStudySection platform;
};
std::unique_ptr<KindSections> read_platform_sections(TomlReader& root, const StudyConfig& cfg);
inline const PlatformSections& platform_sections(const StudyConfig& cfg) { return sections_of<PlatformSections>(cfg); }

}  // namespace poise::kinds::platform_balancing
