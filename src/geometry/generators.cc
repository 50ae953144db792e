#include "geometry/generators.h"

#include <cmath>
#include <map>
#include <numbers>

#include "core/angles.h"
#include "core/error.h"

namespace poise::geometry {
namespace {

using angles::kPi;

double signed_volume(const Mesh& m) {
  double v = 0.0;
  for (const auto& t : m.triangles) v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]]));
  return v / 6.0;
}

// Rotation taking local z to the base x axis (local x -> y, local y -> z).
Eigen::Isometry3d about_x(double x0 = 0.0) {
  Eigen::Matrix3d r;
  r << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  Eigen::Isometry3d f = Eigen::Isometry3d::Identity();
  f.linear() = r;
  f.translation() = Eigen::Vector3d(x0, 0, 0);
  return f;
}

// Rotation taking local z to the base y axis (local x -> z, local y -> x).
Eigen::Isometry3d about_y() {
  Eigen::Matrix3d r;
  r << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  Eigen::Isometry3d f = Eigen::Isometry3d::Identity();
  f.linear() = r;
  return f;
}

}  // namespace

Mesh merge(const Assembly& parts, const std::string& name) {
  Mesh m;
  m.name = name;
  for (const auto& b : parts) m.append(b.mesh);
  return m;
}

double equal_area_radius(double r, int segments) {
  const double a = 2.0 * kPi / segments;
  return r * std::sqrt(a / std::sin(a));
}

Mesh revolve(const std::vector<Eigen::Vector2d>& profile, int segments, const std::string& name,
             const Eigen::Isometry3d& frame) {
  require(profile.size() >= 3 && segments >= 3, "revolve: a profile of at least 3 points and 3 segments");
  Mesh m;
  m.name = name;
  std::vector<std::vector<std::uint32_t>> ring(profile.size());
  for (std::size_t i = 0; i < profile.size(); ++i) {
    const double a = profile[i].x(), r = profile[i].y();
    require(r >= 0.0, "revolve: negative radius in the profile of " + name);
    if (r == 0.0) {
      ring[i].assign(segments, static_cast<std::uint32_t>(m.vertices.size()));
      m.vertices.emplace_back(0.0, 0.0, a);
      continue;
    }
    for (int j = 0; j < segments; ++j) {
      const double th = 2.0 * kPi * j / segments;
      ring[i].push_back(static_cast<std::uint32_t>(m.vertices.size()));
      m.vertices.emplace_back(r * std::cos(th), r * std::sin(th), a);
    }
  }
  for (std::size_t i = 0; i < profile.size(); ++i) {
    const auto& p = ring[i];
    const auto& q = ring[(i + 1) % profile.size()];
    for (int j = 0; j < segments; ++j) {
      const int k = (j + 1) % segments;
      m.triangles.push_back({p[j], p[k], q[k]});
      m.triangles.push_back({p[j], q[k], q[j]});
    }
  }
  remove_degenerate(m);
  if (signed_volume(m) < 0) m.flip();
  m.transform(frame);
  return m;
}

Mesh cylinder(double r, double z0, double z1, int segments, const std::string& name, const Eigen::Isometry3d& frame) {
  const double re = equal_area_radius(r, segments);
  return revolve({{z0, 0.0}, {z0, re}, {z1, re}, {z1, 0.0}}, segments, name, frame);
}

Mesh tube(double r_in, double r_out, double z0, double z1, int segments, const std::string& name,
          const Eigen::Isometry3d& frame) {
  const double ri = equal_area_radius(r_in, segments), ro = equal_area_radius(r_out, segments);
  return revolve({{z0, ri}, {z0, ro}, {z1, ro}, {z1, ri}}, segments, name, frame);
}

Mesh box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int n, const std::string& name) {
  require(n >= 1, "box: at least one subdivision");
  Mesh m;
  m.name = name;
  // Each face: a grid over two axes (u, v) at a fixed coordinate of the third; vertices are
  // shared along the box edges through a map of integer lattice positions.
  std::map<std::array<int, 3>, std::uint32_t> index;
  auto vertex = [&](std::array<int, 3> g) {
    auto [it, inserted] = index.try_emplace(g, static_cast<std::uint32_t>(m.vertices.size()));
    if (inserted) {
      Eigen::Vector3d p;
      for (int k = 0; k < 3; ++k) p[k] = lo[k] + (hi[k] - lo[k]) * g[k] / n;
      m.vertices.push_back(p);
    }
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          std::array<int, 3> g00{}, g10{}, g11{}, g01{};
          for (auto* g : {&g00, &g10, &g11, &g01}) (*g)[axis] = side * n;
          g00[u] = i, g00[v] = j;
          g10[u] = i + 1, g10[v] = j;
          g11[u] = i + 1, g11[v] = j + 1;
          g01[u] = i, g01[v] = j + 1;
          // (u, v, axis) is right-handed: counter-clockwise in (u, v) faces +axis.
          if (side == 1) {
            m.triangles.push_back({vertex(g00), vertex(g10), vertex(g11)});
            m.triangles.push_back({vertex(g00), vertex(g11), vertex(g01)});
          } else {
            m.triangles.push_back({vertex(g00), vertex(g11), vertex(g10)});
            m.triangles.push_back({vertex(g00), vertex(g01), vertex(g11)});
          }
        }
      }
    }
  }
  return m;
}

std::vector<DiskHole> yang2015_hole_pattern(double d, double b_offset, double r_a, double r_b) {
  std::vector<DiskHole> holes;
  holes.reserve(16);
  for (int k = 0; k < 8; ++k) holes.push_back({r_a, k * kPi / 4.0, d});
  for (int k = 0; k < 8; ++k) holes.push_back({r_b, k * kPi / 4.0 + b_offset, d});
  return holes;
}

Assembly simulator_disk(const DiskSpec& s) {
  require(s.radius > 0 && s.thickness > 0 && s.density > 0, "simulator_disk: positive radius, thickness and density");
  const Eigen::Vector2d wedge_dir(std::cos(s.wedge_angle), std::sin(s.wedge_angle));
  const double slope = s.wedge / (2.0 * s.radius);
  // Vertices on the nominal top plane z = thickness move onto the as-built top face.
  auto tilt_top = [&](Mesh& m) {
    for (auto& v : m.vertices) {
      if (v.z() == s.thickness) v.z() += slope * (v.x() * wedge_dir.x() + v.y() * wedge_dir.y());
    }
  };
  Assembly parts;
  Body disk{cylinder(s.radius, 0.0, s.thickness, s.segments, "disk"), s.density};
  tilt_top(disk.mesh);
  parts.push_back(std::move(disk));
  for (std::size_t k = 0; k < s.holes.size(); ++k) {
    const DiskHole& h = s.holes[k];
    require(h.diameter > 0 && h.radius + h.diameter / 2 < s.radius,
            "simulator_disk: hole " + std::to_string(k) + " outside the disk");
    Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
    at.translation() = Eigen::Vector3d(h.radius * std::cos(h.angle), h.radius * std::sin(h.angle), 0.0);
    Mesh hole = cylinder(h.diameter / 2, 0.0, s.thickness, s.hole_segments, "hole_" + std::to_string(k), at);
    tilt_top(hole);
    hole.flip();
    parts.push_back({std::move(hole), s.density});
  }
  for (const DiskClump& c : s.clumps) {
    require(c.hole < s.holes.size() && c.mass > 0 && c.density > 0 && c.diameter > 0,
            "simulator_disk: a clump in a hole that exists, with positive mass, density and diameter");
    const DiskHole& h = s.holes[c.hole];
    const double r = c.diameter / 2;
    const double length = c.mass / (c.density * kPi * r * r);
    Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
    at.translation() = Eigen::Vector3d(h.radius * std::cos(h.angle), h.radius * std::sin(h.angle), 0.0);
    parts.push_back(
        {cylinder(r, s.thickness, s.thickness + length, s.hole_segments, "clump_on_hole_" + std::to_string(c.hole), at),
         c.density});
  }
  return parts;
}

std::string check_seeker_geometry(const SeekerGeometry& g) {
  // Only what makes the parts impossible to build. Spans that make frames collide are not
  // errors: they show as negative clearance (interference), which a sizing study can use.
  if (g.pitch_span / 2 - g.bearing_width / 2 <= 0) return "pitch_span must exceed bearing_width";
  if (g.yaw_span / 2 - g.bearing_width / 2 - g.ring_gap - g.ring_section <= 0) {
    return "yaw_span must exceed bearing_width + 2 (ring_gap + ring_section)";
  }
  if (g.barrel_wall >= g.barrel_radius) return "barrel_wall must be thinner than barrel_radius";
  if (g.aperture_radius >= g.barrel_radius - g.barrel_wall)
    return "aperture_radius must be smaller than the barrel's bore";
  if (!(g.barrel_back < g.detector_x && g.detector_x < g.barrel_front)) return "detector_x must lie inside the barrel";
  if (g.window_radius >= g.housing_radius) return "window_radius must be smaller than housing_radius";
  if (!(g.housing_back < g.barrel_back && g.front_x > g.barrel_front))
    return "the housing must extend past both ends of the barrel";
  if (g.segments < 8) return "segments must be at least 8";
  return "";
}

SeekerMeshes seeker_meshes(const SeekerGeometry& g) {
  if (const std::string why = check_seeker_geometry(g); !why.empty()) throw Error("seeker geometry: " + why);
  SeekerMeshes m;
  const double y_in = g.pitch_span / 2 - g.bearing_width / 2, y_out = g.pitch_span / 2 + g.bearing_width / 2;
  const double z_out = g.yaw_span / 2 - g.bearing_width / 2 - g.ring_gap, z_in = z_out - g.ring_section;
  const double hx = g.ring_depth / 2;
  const int n = 4;
  m.ring.name = "yaw_ring";
  // Sides (holding the pitch bearings) span the full height; top and bottom members between them.
  m.ring.append(box({-hx, y_in, -z_out}, {hx, y_out, z_out}, n, "side+"));
  m.ring.append(box({-hx, -y_out, -z_out}, {hx, -y_in, z_out}, n, "side-"));
  m.ring.append(box({-hx, -y_in, z_in}, {hx, y_in, z_out}, n, "top"));
  m.ring.append(box({-hx, -y_in, -z_out}, {hx, y_in, -z_in}, n, "bottom"));
  m.barrel = tube(g.barrel_radius - g.barrel_wall, g.barrel_radius, g.barrel_back, g.barrel_front, g.segments, "barrel",
                  about_x());
  m.pitch_shafts.name = "pitch_shafts";
  Eigen::Isometry3d fy = about_y();
  m.pitch_shafts.append(cylinder(g.shaft_radius, g.barrel_radius - g.barrel_wall / 2, y_in, 24, "", fy));
  m.pitch_shafts.append(cylinder(g.shaft_radius, -y_in, -(g.barrel_radius - g.barrel_wall / 2), 24, "", fy));
  const double ro = g.housing_radius + g.housing_wall, xf = g.front_x + g.front_wall;
  m.housing = revolve({{g.housing_back, g.housing_radius},
                       {g.housing_back, ro},
                       {xf, ro},
                       {xf, g.window_radius},
                       {g.front_x, g.window_radius},
                       {g.front_x, g.housing_radius}},
                      g.segments, "housing", about_x());
  m.posts.name = "yaw_posts";
  const double zb = g.yaw_span / 2 - g.bearing_width / 2;
  m.posts.append(cylinder(g.post_radius, zb, ro, 32, "post+"));
  m.posts.append(cylinder(g.post_radius, -ro, -zb, 32, "post-"));
  m.window = revolve({{g.front_x, 0.0}, {g.front_x, g.window_radius}, {xf, g.window_radius}, {xf, 0.0}}, g.segments,
                     "window", about_x());
  return m;
}

}  // namespace poise::geometry
