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
///
/// A designer's CAD in place of the generated frames and housing (optional, "" = generated):
///   ring_mesh = "meshes/ring.stl"        # the yaw frame, in yaw-frame coordinates
///   barrel_mesh = "meshes/barrel.stl"    # the pitch frame's barrel, in pitch-frame coordinates
///   housing_mesh = "meshes/housing.stl"  # the housing, in base coordinates
///   mesh_unit = "mm"                     # mm | cm | m | in, of the three files
/// Each file (STL or OBJ, relative to the model file) is checked as `poise mass-properties`
/// checks it (closed, manifold, consistently oriented) and refused at its key otherwise. A mesh
/// is used as drawn: a span override no longer resizes it. The beam (detector plane, aperture),
/// the window, the posts and the pitch shafts still come from the dimensions above.
#include <optional>
#include <string>

#include "engine/study_files/toml_reader.h"
#include "geometry/generators.h"
#include "model_files/seeker_model.h"

namespace poise::model_files {
using engine::TomlReader;

/// Reads [geometry] if present (std::nullopt if not), and its meshes into `meshes` (relative to
/// `base_dir`); errors go to the reader's context.
std::optional<geometry::SeekerGeometry> read_seeker_geometry(TomlReader& root, double yaw_span, double pitch_span,
                                                             const std::string& base_dir,
                                                             SeekerModel::UserMeshes& meshes);

/// The seeker's parts for its scenes: generated from the model's [geometry], the ring, barrel and
/// housing replaced by the designer's meshes where given. Throws poise::Error without [geometry].
geometry::SeekerMeshes seeker_scene_meshes(const SeekerModel& model);

}  // namespace poise::model_files
