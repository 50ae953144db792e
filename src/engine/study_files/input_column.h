#pragma once
/// One sampled input of a study, as a column of samples.csv.
#include <string>

namespace poise::engine {

struct InputColumn {
  std::string name;             ///< e.g. "yaw_radial_runout_A_um"
  std::string unit;             ///< its display unit, e.g. "um" ("1" for a pure number)
  double display_factor = 1.0;  ///< SI per display unit
};

}  // namespace poise::engine
