#pragma once
/// The shafting LOS line of the platform's combined budget: the study named in
/// [platform.shafting] (any kind) evaluated in memory through the kind interface, its `output`
/// (an angle: each unit's greatest LOS error over the field of regard) and `pixel_output` (the
/// same error in px) by the units they are declared in; the pixel's angle is their ratio, which
/// must be the same for every sample (the two outputs are one error in two units).
#include <vector>

#include "engine/study_files/study_config.h"

namespace poise::kinds::platform_balancing {
using engine::StudyConfig;

/// Each unit's shafting LOS error (arcsec, sorted) and the pixel IFOV (arcsec).
struct ShaftingLos {
  std::vector<double> los_max_arcsec;
  double pixel_arcsec = 0.0;
};

/// Checks the [platform.shafting] study's outputs (present, an angle and a pixel count);
/// throws poise::Error naming the study file and the key.
void check_shafting_study(const StudyConfig& cfg);

/// The line (empty without [platform.shafting]). Throws poise::Error as check_shafting_study
/// does, or when the pixel's angle differs between samples.
ShaftingLos compute_shafting_los(const StudyConfig& cfg, int threads);

}  // namespace poise::kinds::platform_balancing
