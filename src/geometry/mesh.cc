#include "geometry/mesh.h"

#include <algorithm>
#include <map>
#include <utility>

namespace poise::geometry {

void Mesh::append(const Mesh& other) {
  const auto base = static_cast<std::uint32_t>(vertices.size());
  if (triangle_lines.size() == triangles.size() && other.triangle_lines.size() == other.triangles.size() &&
      !(triangles.empty() && other.triangles.empty())) {
    triangle_lines.insert(triangle_lines.end(), other.triangle_lines.begin(), other.triangle_lines.end());
  } else {
    triangle_lines.clear();
  }
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const Triangle& t : other.triangles) triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

void Mesh::flip() {
  for (Triangle& t : triangles) std::swap(t[1], t[2]);
}

void Mesh::transform(const Eigen::Isometry3d& pose) {
  for (auto& v : vertices) v = pose * v;
}

Eigen::Vector3d Mesh::face_normal(std::size_t k) const {
  const Triangle& t = triangles[k];
  const Eigen::Vector3d& a = vertices[t[0]];
  return (vertices[t[1]] - a).cross(vertices[t[2]] - a);
}

Eigen::AlignedBox3d Mesh::bounds() const {
  Eigen::AlignedBox3d box;
  for (const auto& v : vertices) box.extend(v);
  return box;
}

std::string check_closed(const Mesh& mesh) {
  // Count directed edges; a closed, consistently oriented mesh pairs each (a, b) with (b, a).
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> count;
  for (const Triangle& t : mesh.triangles) {
    for (int e = 0; e < 3; ++e) ++count[{t[e], t[(e + 1) % 3]}];
  }
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    const Triangle& t = mesh.triangles[k];
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = t[e], b = t[(e + 1) % 3];
      const std::string edge = "edge (" + std::to_string(a) + ", " + std::to_string(b) + ")";
      if (count[{a, b}] > 1) {
        return "triangle " + std::to_string(k) + ": " + edge +
               " is used twice in the same direction (inconsistent orientation or a non-manifold edge)";
      }
      const auto it = count.find({b, a});
      if (it == count.end() || it->second == 0) {
        return "triangle " + std::to_string(k) + ": " + edge + " has no opposite edge (the mesh is open)";
      }
    }
  }
  return "";
}

void remove_degenerate(Mesh& mesh) {
  auto bad = [](const Triangle& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; };
  if (mesh.triangle_lines.size() == mesh.triangles.size()) {
    std::size_t out = 0;
    for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
      if (bad(mesh.triangles[k])) continue;
      mesh.triangles[out] = mesh.triangles[k];
      mesh.triangle_lines[out++] = mesh.triangle_lines[k];
    }
    mesh.triangles.resize(out);
    mesh.triangle_lines.resize(out);
    return;
  }
  mesh.triangle_lines.clear();
  std::erase_if(mesh.triangles, bad);
}

void remove_triangles(Mesh& mesh, const std::vector<std::size_t>& ascending) {
  if (ascending.empty()) return;
  const bool lines = mesh.triangle_lines.size() == mesh.triangles.size();
  std::size_t out = 0, next = 0;
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    if (next < ascending.size() && ascending[next] == k) {
      ++next;
      continue;
    }
    mesh.triangles[out] = mesh.triangles[k];
    if (lines) mesh.triangle_lines[out] = mesh.triangle_lines[k];
    ++out;
  }
  mesh.triangles.resize(out);
  if (lines) {
    mesh.triangle_lines.resize(out);
  } else {
    mesh.triangle_lines.clear();
  }
}

}  // namespace poise::geometry
