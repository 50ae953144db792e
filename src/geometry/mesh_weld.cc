#include "geometry/mesh_weld.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace poise::geometry {
namespace {

using Cell = std::array<std::int64_t, 3>;

struct CellHash {
  std::size_t operator()(const Cell& c) const {
    std::uint64_t h = 1469598103934665603ull;
    for (std::int64_t v : c) h = (h ^ static_cast<std::uint64_t>(v)) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};

}  // namespace

double default_weld_tolerance(const Mesh& mesh) {
  if (mesh.vertices.empty()) return 0.0;
  return kWeldRelative * mesh.bounds().diagonal().norm();
}

WeldReport weld_vertices(Mesh& mesh, double tolerance_m) {
  WeldReport r;
  r.tolerance_m = tolerance_m;
  if (!(tolerance_m > 0.0) || mesh.vertices.empty()) return r;
  std::unordered_map<Cell, std::vector<std::uint32_t>, CellHash> cells;
  cells.reserve(mesh.vertices.size());
  std::vector<std::uint32_t> to(mesh.vertices.size());
  std::vector<Eigen::Vector3d> kept;
  kept.reserve(mesh.vertices.size());
  auto cell_of = [&](const Eigen::Vector3d& v) {
    return Cell{static_cast<std::int64_t>(std::floor(v.x() / tolerance_m)),
                static_cast<std::int64_t>(std::floor(v.y() / tolerance_m)),
                static_cast<std::int64_t>(std::floor(v.z() / tolerance_m))};
  };
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d& v = mesh.vertices[i];
    const Cell c = cell_of(v);
    bool found = false;
    for (std::int64_t dx = -1; dx <= 1 && !found; ++dx) {
      for (std::int64_t dy = -1; dy <= 1 && !found; ++dy) {
        for (std::int64_t dz = -1; dz <= 1 && !found; ++dz) {
          const auto it = cells.find(Cell{c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == cells.end()) continue;
          for (std::uint32_t k : it->second) {
            if ((kept[k] - v).cwiseAbs().maxCoeff() <= tolerance_m) {
              to[i] = k;
              found = true;
              break;
            }
          }
        }
      }
    }
    if (!found) {
      to[i] = static_cast<std::uint32_t>(kept.size());
      cells[c].push_back(to[i]);
      kept.push_back(v);
    }
  }
  // Vertices no triangle uses are not counted as merged: only those that moved onto another.
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const auto& t : mesh.triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
  std::vector<char> target_used(kept.size(), 0);
  for (std::size_t i = 0; i < to.size(); ++i) {
    if (!used[i]) continue;
    if (target_used[to[i]]) ++r.merged_vertices;
    target_used[to[i]] = 1;
  }
  std::size_t out = 0;
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    const Triangle t{to[mesh.triangles[k][0]], to[mesh.triangles[k][1]], to[mesh.triangles[k][2]]};
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      ++r.dropped_triangles;
      continue;
    }
    mesh.triangles[out] = t;
    if (k < mesh.triangle_lines.size()) mesh.triangle_lines[out] = mesh.triangle_lines[k];
    ++out;
  }
  mesh.triangles.resize(out);
  if (!mesh.triangle_lines.empty()) mesh.triangle_lines.resize(out);
  mesh.vertices = std::move(kept);
  return r;
}

}  // namespace poise::geometry
