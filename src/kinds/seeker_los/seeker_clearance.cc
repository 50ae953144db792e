#include "kinds/seeker_los/seeker_clearance.h"

#include <algorithm>
#include <limits>

#include "core/error.h"
#include "geometry/obstruction.h"
#include "model_files/seeker_geometry.h"

namespace poise::kinds::seeker_los {
using namespace poise::engine;
using namespace poise::model_files;

double nominal_min_clearance(const SeekerModel& model, std::size_t yaw_points, std::size_t pitch_points) {
  if (!model.geometry)
    throw Error(model.file + ": a [clearance] output needs a [geometry] section in the seeker model");
  const geometry::SeekerScenes scenes(*model.geometry, seeker_scene_meshes(model), 1);
  double best = std::numeric_limits<double>::infinity();
  for (double a : models::linspace(model.yaw_min, model.yaw_max, yaw_points)) {
    for (double b : models::linspace(model.pitch_min, model.pitch_max, pitch_points)) {
      best = std::min(best, scenes.clearance(geometry::nominal_pose(a, b)).min());
    }
  }
  return best;
}

}  // namespace poise::kinds::seeker_los
