#pragma once
/// The platform study's own report sections (PlatformStudy::report_sections, details) and
/// the shafting LOS line it combines with the balancing residual.
#include <vector>

#include "engine/study_files/study_config.h"

namespace poise::kinds::platform_balancing {
using engine::StudyConfig;

/// The shafting LOS error of the seeker study named in [platform.shafting]: the greatest
/// error over the field of regard of each unit (arcsec), and the pixel IFOV (arcsec).
struct ShaftingLos {
  std::vector<double> los_max_arcsec;
  double pixel_arcsec = 0.0;
};
ShaftingLos compute_shafting_los(const StudyConfig& cfg, int threads);

}  // namespace poise::kinds::platform_balancing
