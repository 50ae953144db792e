#include "model_files/disk_geometry_model.h"

#include <cmath>
#include <numbers>
#include <utility>

#include "core/error.h"
#include "core/units.h"
#include "engine/study_files/model_overrides.h"

namespace poise::model_files {
using namespace poise::engine;
namespace {
using units::kDensity;
}  // namespace

DiskGeometryModel load_disk_geometry_model(const std::string& path,
                                           const std::map<std::string, std::string>& overrides) {
  auto [doc, ctx] = open_model_file(path, overrides);
  TomlReader root(doc, ctx);
  DiskGeometryModel m;
  static_cast<ModelHeader&>(m) = read_model_header(root, "simulator_disk");
  geometry::DiskSpec& s = m.nominal;
  {
    TomlReader t = root.table("disk");
    s.radius = t.quantity("radius", units::kLength, positive);
    s.thickness = t.quantity("thickness", units::kLength, positive);
    s.density = t.quantity("density", kDensity, positive);
    s.segments = static_cast<int>(t.integer("segments", 16, 4096, 256));
    t.accept_notes();
  }
  {
    TomlReader t = root.table("holes");
    const double d = t.quantity("diameter", units::kLength, positive);
    const double ra = t.quantity("circle_a_radius", units::kLength, positive);
    const double rb = t.quantity("circle_b_radius", units::kLength, positive);
    const double off = t.quantity("circle_b_offset", units::kAngle);
    s.hole_segments = static_cast<int>(t.integer("segments", 8, 1024, 48));
    t.accept_notes();
    if (s.radius > 0 && ra + d / 2 >= s.radius) {
      t.error("circle_a_radius", units::format(ra, "mm"),
              "holes inside the disk (circle radius + diameter/2 < disk radius)");
    }
    if (d > 0 && std::abs(ra - rb) < d) {
      t.error("circle_b_radius", units::format(rb, "mm"), "circles at least one hole diameter apart");
    }
    if (d > 0 && 2 * rb * std::sin(std::numbers::pi / 8) <= d) {
      t.error("circle_b_radius", units::format(rb, "mm"),
              "holes of circle B apart from each other (2 r sin(22.5 deg) > diameter)");
    }
    s.holes = geometry::yang2015_hole_pattern(d, off, ra, rb);
  }
  for (auto& c : root.table_array("clump")) {
    geometry::DiskClump clump;
    const std::string circle = c.choice("circle", {"A", "B"});
    const auto index = static_cast<std::size_t>(c.integer("hole", 0, 7));
    clump.hole = index + (circle == "B" ? 8 : 0);
    clump.mass = c.quantity("mass", units::kMass, positive);
    clump.diameter = c.quantity("diameter", units::kLength, positive);
    clump.density = c.quantity("density", kDensity, positive);
    c.accept_notes();
    for (const auto& other : s.clumps) {
      if (other.hole == clump.hole) c.error("hole", std::to_string(index), "a hole no other clump weight uses");
    }
    s.clumps.push_back(clump);
  }
  {
    TomlReader t = root.table("tolerances");
    m.hole_position = read_tolerance(t, "hole_position", units::kLength, "mm");
    m.clump_mass = read_tolerance(t, "clump_mass", units::kMass, "g");
    m.thickness = read_tolerance(t, "thickness", units::kLength, "mm");
    m.wedge = read_tolerance(t, "wedge", units::kLength, "mm");
  }
  finish(doc, *ctx);
  return m;
}

DiskSampler::DiskSampler(DiskGeometryModel model) : model_(std::move(model)) {
  const double mm = 1e-3;
  for (std::size_t k = 0; k < model_.nominal.holes.size(); ++k) {
    const std::string h = std::string(k < 8 ? "A" : "B") + std::to_string(k % 8);
    columns_.push_back({"hole_" + h + "_dx_mm", "mm", mm});
    columns_.push_back({"hole_" + h + "_dy_mm", "mm", mm});
  }
  for (const auto& c : model_.nominal.clumps) {
    columns_.push_back(
        {"clump_" + std::string(c.hole < 8 ? "A" : "B") + std::to_string(c.hole % 8) + "_dm_g", "g", 1e-3});
  }
  columns_.push_back({"thickness_dev_mm", "mm", mm});
  columns_.push_back({"wedge_mm", "mm", mm});
  columns_.push_back({"wedge_angle_deg", "deg", units::kRadPerDeg});
}

geometry::DiskSpec DiskSampler::draw(std::span<const double> u, std::span<double> values) const {
  std::size_t k = 0;
  auto put = [&](double v) { values[k++] = v; };
  for (std::size_t h = 0; h < model_.nominal.holes.size(); ++h) {
    put(model_.hole_position.dist.quantile(u[k]));  // position error (dx, dy) of the centre, disk frame
    put(model_.hole_position.dist.quantile(u[k]));
  }
  for (std::size_t c = 0; c < model_.nominal.clumps.size(); ++c) put(model_.clump_mass.dist.quantile(u[k]));
  put(model_.thickness.dist.quantile(u[k]));
  put(model_.wedge.dist.magnitude_quantile(u[k]));
  put(2.0 * std::numbers::pi * u[k]);
  geometry::DiskSpec s = spec_of(values);  // not const: returned by move
  for (std::size_t i = 0; i < values.size(); ++i) values[i] /= columns_[i].display_factor;
  return s;
}

geometry::DiskSpec DiskSampler::spec_of(std::span<const double> si) const {
  if (si.size() != dimension()) throw Error("disk sampler: input values of the wrong size");
  geometry::DiskSpec s = model_.nominal;
  std::size_t k = 0;
  for (auto& h : s.holes) {
    const double x = h.radius * std::cos(h.angle) + si[k++];
    const double y = h.radius * std::sin(h.angle) + si[k++];
    h.radius = std::hypot(x, y);
    h.angle = std::atan2(y, x);
  }
  for (auto& c : s.clumps) c.mass += si[k++];
  s.thickness += si[k++];
  s.wedge = si[k++];
  s.wedge_angle = si[k++];
  return s;
}

std::vector<double> DiskSampler::nominal() const { return std::vector<double>(dimension(), 0.0); }

}  // namespace poise::model_files
