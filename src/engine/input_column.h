#pragma once
/// One sampled input of a study, as a column of samples.csv.
#include <string>

namespace poise::studies {

struct InputColumn {
  std::string name;  ///< e.g. "yaw_radial_runout_A_um"
  double display_factor = 1.0;
  /// The model file's tolerance key it is drawn from ("yaw.radial_runout"): the columns of
  /// one tolerance (amplitude, phase, each bearing) form its group in the Sobol indices.
  std::string tolerance;
};

}  // namespace poise::studies
