#pragma once
/// The optional [geometry] section of a seeker model (models/seeker_two_axis_*.toml): the
/// dimensions of the yaw ring, the optical barrel and the housing (geometry/generators.h).
/// The frames follow the model's bearing spans: the ring's height from yaw.bearing_span, its
/// width from pitch.bearing_span, so an override or sweep of a span resizes the frames and
/// moves their clearance to the housing with it.
///
///   [geometry]
///   bearing_width = "7 mm"     ring_section = "6 mm"   ring_depth = "20 mm"  ring_gap = "1 mm"
///   barrel_radius = "20 mm"    barrel_wall = "2 mm"    barrel_back = "-30 mm" barrel_front = "40 mm"
///   aperture_radius = "15 mm"  detector_x = "-25 mm"
///   housing_radius = "58 mm"   housing_wall = "3 mm"   housing_back = "-80 mm"
///   front_x = "75 mm"          front_wall = "4 mm"     window_radius = "55 mm"
///   post_radius = "10 mm"      segments = 96           notes = "..."
#include <optional>

#include "geometry/generators.h"
#include "engine/toml_reader.h"

namespace poise::studies {

/// Reads [geometry] if present (std::nullopt if not); errors go to the reader's context.
std::optional<geometry::SeekerGeometry> read_seeker_geometry(TomlReader& root, double yaw_span, double pitch_span);

}  // namespace poise::studies
