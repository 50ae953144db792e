#include "model_files/seeker_geometry.h"

#include <filesystem>

#include "core/error.h"
#include "engine/study_files/model_overrides.h"
#include "engine/study_files/user_parts.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"

namespace poise::model_files {
using namespace poise::engine;
namespace {

// One optional mesh key: "" = generated; else loaded, checked and shared, refused at its key.
std::shared_ptr<const geometry::Mesh> read_mesh(TomlReader& t, const char* key, const std::string& unit,
                                                const std::string& base_dir, std::string& resolved) {
  const std::string file = t.string(key, "");
  if (file.empty() || t.schema_only()) return nullptr;
  const std::filesystem::path p =
      std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : std::filesystem::path(base_dir) / file;
  resolved = p.lexically_normal().string();
  try {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(resolved, ec)) throw Error(resolved + ": no such mesh file");
    auto mesh = std::make_shared<geometry::Mesh>(geometry::load_mesh(resolved, mesh_unit_size(unit)));
    geometry::require_valid_mesh(*mesh);
    if (mesh->name.empty()) mesh->name = key;
    return mesh;
  } catch (const Error& e) {
    t.error(key, quote_value(file),
            "\"\" (generated) or a closed, consistently oriented mesh file (STL or OBJ): " + std::string(e.what()));
  }
  return nullptr;
}

}  // namespace

std::optional<geometry::SeekerGeometry> read_seeker_geometry(TomlReader& root, double yaw_span, double pitch_span,
                                                             const std::string& base_dir,
                                                             SeekerModel::UserMeshes& meshes) {
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
  const std::string unit = t.choice("mesh_unit", {"mm", "cm", "m", "in"}, "mm");
  meshes.ring = read_mesh(t, "ring_mesh", unit, base_dir, meshes.ring_file);
  meshes.barrel = read_mesh(t, "barrel_mesh", unit, base_dir, meshes.barrel_file);
  meshes.housing = read_mesh(t, "housing_mesh", unit, base_dir, meshes.housing_file);
  t.accept_notes();
  if (t.context().errors.empty()) {
    if (const std::string why = geometry::check_seeker_geometry(g); !why.empty()) {
      t.error("window_radius", "", "a consistent seeker geometry: " + why);
    }
  }
  return g;
}

geometry::SeekerMeshes seeker_scene_meshes(const SeekerModel& model) {
  if (!model.geometry) throw Error(model.file + ": the seeker's frames and housing need a [geometry] section");
  geometry::SeekerMeshes parts = geometry::seeker_meshes(*model.geometry);
  if (model.meshes.ring) parts.ring = *model.meshes.ring;
  if (model.meshes.barrel) parts.barrel = *model.meshes.barrel;
  if (model.meshes.housing) parts.housing = *model.meshes.housing;
  return parts;
}

}  // namespace poise::model_files
