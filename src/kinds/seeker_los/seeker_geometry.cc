#include "kinds/seeker_los/seeker_geometry.h"

namespace poise::studies {

std::optional<geometry::SeekerGeometry> read_seeker_geometry(TomlReader& root, double yaw_span, double pitch_span) {
  if (!root.has_or_schema("geometry")) return std::nullopt;
  TomlReader t = root.table("geometry");
  geometry::SeekerGeometry g;
  g.yaw_span = yaw_span;
  g.pitch_span = pitch_span;
  const auto len = [&](const char* key, auto check) { return t.quantity(key, units::kLength, check); };
  g.bearing_width = len("bearing_width", positive);
  g.ring_section = len("ring_section", positive);
  g.ring_depth = len("ring_depth", positive);
  g.ring_gap = len("ring_gap", non_negative);
  g.barrel_radius = len("barrel_radius", positive);
  g.barrel_wall = len("barrel_wall", positive);
  g.barrel_back = t.quantity("barrel_back", units::kLength);
  g.barrel_front = t.quantity("barrel_front", units::kLength);
  g.aperture_radius = len("aperture_radius", positive);
  g.detector_x = t.quantity("detector_x", units::kLength);
  g.housing_radius = len("housing_radius", positive);
  g.housing_wall = len("housing_wall", positive);
  g.housing_back = t.quantity("housing_back", units::kLength);
  g.front_x = len("front_x", positive);
  g.front_wall = len("front_wall", positive);
  g.window_radius = len("window_radius", positive);
  g.post_radius = len("post_radius", positive);
  g.segments = static_cast<int>(t.integer("segments", 8, 2048, 96));
  t.accept_notes();
  if (t.context().errors.empty()) {
    if (const std::string why = geometry::check_seeker_geometry(g); !why.empty()) {
      t.error("window_radius", "", "a consistent seeker geometry: " + why);
    }
  }
  return g;
}

}  // namespace poise::studies
