#include "engine/study_files/user_parts.h"

#include <cmath>
#include <filesystem>
#include <set>
#include <utility>

#include "core/format.h"
#include "core/units.h"
#include "engine/study_files/model_overrides.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"

namespace poise::engine {
namespace {

// The share of a part's volume that overlapping shells may take: "1e-06".
std::string overlap_share_text() { return significant(geometry::kMaxOverlapShare, 6); }

using units::kDensity;

// Three quantities of one dimension ["1 mm", "2 mm", "3 mm"]; a missing key is zero.
Eigen::Vector3d read_triple(TomlReader& t, const std::string& key, const units::Dimension& dim,
                            const std::string& example) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  if (t.schema_only()) {  // optional: `poise keys` lists it with its default
    t.ask(key, "three quantities (x, y, z), e.g. " + example, "zero", false);
    return v;
  }
  if (!t.has(key)) return v;
  const std::vector<std::string> items = t.string_array(key);
  if (items.size() != 3) {
    t.error(key, std::to_string(items.size()) + " values", "three values (x, y, z), e.g. " + example);
    return v;
  }
  for (int i = 0; i < 3; ++i) {
    try {
      v[i] = units::parse_as(items[i], dim);
    } catch (const Error& e) {
      t.error(key, quote_value(items[i]), std::string(e.what()) + " (x, y, z, e.g. " + example + ")");
    }
  }
  return v;
}

}  // namespace

double mesh_unit_size(const std::string& unit) {
  return unit == "mm" ? 1e-3 : unit == "cm" ? 1e-2 : unit == "in" ? 0.0254 : 1.0;
}

UserParts read_user_parts(TomlReader& table, const std::string& base_dir) {
  UserParts out;
  std::set<std::string> names;
  for (TomlReader& t : table.table_array("part")) {
    UserPart p;
    const std::size_t errors_before = t.context().errors.size();
    p.part.name = t.string("name");
    if (!p.part.name.empty() && !names.insert(p.part.name).second) {
      t.error("name", quote_value(p.part.name), "a name no other part has");
    }
    const std::string mesh = t.string("mesh");
    p.unit = t.choice("unit", {"mm", "cm", "m", "in"});
    p.part.density = t.quantity("density", kDensity, positive);
    const Eigen::Vector3d translation =
        read_triple(t, "translation", units::kLength, "[\"0 mm\", \"0 mm\", \"12 mm\"]");
    const Eigen::Vector3d rotation = read_triple(t, "rotation", units::kAngle, "[\"0 deg\", \"0 deg\", \"30 deg\"]");
    p.part.placement = Eigen::Isometry3d::Identity();
    p.part.placement.linear() = (Eigen::AngleAxisd(rotation.z(), Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(rotation.y(), Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(rotation.x(), Eigen::Vector3d::UnitX()))
                                    .toRotationMatrix();
    p.part.placement.translation() = translation;
    if (t.has_or_schema("tolerances")) {  // gated so that `poise keys` lists the tolerances
      TomlReader tol = t.table("tolerances");
      if ((p.has_density = tol.has_or_schema("density")))
        p.density = read_tolerance(tol, "density", kDensity, "kg/m^3");
      if ((p.has_position = tol.has_or_schema("position")))
        p.position = read_tolerance(tol, "position", units::kLength, "mm");
      if ((p.has_angle = tol.has_or_schema("angle"))) p.angle = read_tolerance(tol, "angle", units::kAngle, "deg");
      if ((p.has_scale = tol.has_or_schema("scale"))) p.scale = read_tolerance(tol, "scale", units::kDimensionless, "");
    }
    t.accept_notes();
    if (mesh.empty() || t.context().errors.size() != errors_before) {
      out.parts.push_back(std::move(p));
      continue;
    }
    const std::filesystem::path resolved = std::filesystem::path(mesh).is_absolute()
                                               ? std::filesystem::path(mesh)
                                               : std::filesystem::path(base_dir) / mesh;
    p.mesh_file = resolved.lexically_normal().string();
    try {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(p.mesh_file, ec)) throw Error(p.mesh_file + ": no such mesh file");
      const double unit_m = mesh_unit_size(p.unit);
      const geometry::Mesh m = geometry::load_mesh(p.mesh_file, unit_m);
      const geometry::MeshCheck check = geometry::require_valid_mesh(m);
      // Closed shells that enclose common material would count it twice: found by rays.
      geometry::RayGridOptions grid;
      grid.rays_per_side = 96;
      m.bounds().sizes().minCoeff(&grid.axis);
      geometry::RayCastStats stats;
      geometry::raycast_moments({{m, 1.0}}, grid, &stats);
      // Touching curved faces whose facets cross by their chord error overlap by a trace.
      if (stats.overlap_rays > 0 && stats.overlap_volume_m3 > geometry::kMaxOverlapShare * check.volume_m3) {
        throw Error(p.mesh_file + ": shells overlap: " + std::to_string(stats.overlap_rays) + " of " +
                    std::to_string(stats.rays) + " rays pass through material enclosed by two shells, about " +
                    geometry::describe_volume(m, stats.overlap_volume_m3) + " counted twice, " +
                    geometry::describe_box(m, stats.overlap_box) + " (more than " + overlap_share_text() +
                    " of the part's volume)");
      }
      p.triangles = m.triangles.size();
      p.shells = check.shells.size();
      if (const std::string w = geometry::unit_warning(m, p.unit, unit_m); !w.empty()) out.warnings.push_back(w);
      p.part = geometry::make_assembly_part(p.part.name, m, p.part.density, p.part.placement);
    } catch (const Error& e) {
      t.error("mesh", quote_value(mesh),
              std::string("a closed, consistently oriented mesh file (STL or OBJ): ") + e.what());
    }
    out.parts.push_back(std::move(p));
  }
  return out;
}

UserParts load_user_parts_file(const std::string& path) {
  auto [doc, ctx] = open_model_file(path, {});
  TomlReader root(doc, ctx);
  read_model_header(root, "user_parts");
  TomlReader model = root.table("model");
  model.accept_notes();
  TomlReader geometry = root.table("geometry");
  UserParts parts = read_user_parts(geometry, std::filesystem::path(path).parent_path().string());
  if (parts.parts.empty() && ctx->errors.empty()) geometry.error("part", "", "at least one [[geometry.part]]");
  finish(doc, *ctx);
  return parts;
}

UserPartsSampler::UserPartsSampler(UserParts parts) : parts_(std::move(parts)) {
  for (const auto& p : parts_.parts) {
    nominal_.push_back(p.part);
    const std::string& n = p.part.name;
    if (p.has_density) columns_.push_back({n + "_ddensity_kg_m3", "kg/m^3", 1.0});
    if (p.has_position) {
      for (const char* a : {"x", "y", "z"}) columns_.push_back({n + "_d" + a + "_mm", "mm", 1e-3});
    }
    if (p.has_angle) {
      for (const char* a : {"x", "y", "z"}) columns_.push_back({n + "_r" + a + "_deg", "deg", units::kRadPerDeg});
    }
    if (p.has_scale) columns_.push_back({n + "_scale_ppm", "ppm", 1e-6});
  }
}

std::vector<geometry::PartDeviation> UserPartsSampler::draw(std::span<const double> u, std::span<double> values) const {
  std::vector<geometry::PartDeviation> out(parts_.parts.size());
  std::size_t k = 0;
  auto put = [&](const ToleranceSpec& spec) {
    const double v = spec.dist.quantile(u[k]);
    values[k] = v / columns_[k].display_factor;
    ++k;
    return v;
  };
  for (std::size_t i = 0; i < parts_.parts.size(); ++i) {
    const UserPart& p = parts_.parts[i];
    geometry::PartDeviation& d = out[i];
    if (p.has_density) d.density = put(p.density);
    if (p.has_position) {
      for (int a = 0; a < 3; ++a) d.translation[a] = put(p.position);
    }
    if (p.has_angle) {
      for (int a = 0; a < 3; ++a) d.rotation[a] = put(p.angle);
    }
    if (p.has_scale) d.scale = put(p.scale);
  }
  return out;
}

geometry::MassProperties UserPartsSampler::as_built(std::span<const double> u, std::span<double> values) const {
  return geometry::as_built_assembly(nominal_, draw(u, values));
}

}  // namespace poise::engine
