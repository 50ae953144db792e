#pragma once
/// One sampled input of a study, as a column of samples.csv.
#include <string>

namespace poise::engine {

struct InputColumn {
  std::string name;  ///< e.g. "yaw_radial_runout_A_um"
  double display_factor = 1.0;
};

}  // namespace poise::engine
