#include "geometry/mesh_text.h"

#include <cmath>

#include "core/format.h"

namespace poise::geometry {
namespace {

// What a length in metres is written as: the file's unit if it has a name, else metres.
struct Scale {
  double size_m = 1.0;
  std::string name = "m";
};

Scale scale_of(const Mesh& mesh) {
  const std::string name = unit_name(mesh.unit_m);
  if (name.empty() || !(mesh.unit_m > 0.0)) return {};
  return {mesh.unit_m, name};
}

std::string number(double v, int digits = 6) {
  if (std::abs(v) < 1e-300) v = 0.0;  // no "-0"
  return significant(v, digits);
}

// Rounding residue (1e-15 where the file says 0) is written as 0.
std::string triple(const Eigen::Vector3d& p, double size_m, int digits = 6) {
  const double scale = p.cwiseAbs().maxCoeff();
  auto text = [&](double v) { return number(std::abs(v) <= 1e-12 * scale ? 0.0 : v / size_m, digits); };
  return std::string("(") + text(p.x()) + ", " + text(p.y()) + ", " + text(p.z()) + ")";
}

}  // namespace

std::string unit_name(double unit_m) {
  static const std::pair<const char*, double> kUnits[] = {{"mm", 1e-3}, {"cm", 1e-2}, {"m", 1.0}, {"in", 0.0254}};
  for (const auto& [name, size] : kUnits) {
    if (std::abs(unit_m - size) <= 1e-12 * size) return name;
  }
  return "";
}

std::string describe_point(const Mesh& mesh, const Eigen::Vector3d& p_m) {
  const Scale s = scale_of(mesh);
  return triple(p_m, s.size_m) + " " + s.name;
}

std::string describe_length(const Mesh& mesh, double length_m) {
  const Scale s = scale_of(mesh);
  return number(length_m / s.size_m) + " " + s.name;
}

std::string describe_volume(const Mesh& mesh, double volume_m3) {
  const Scale s = scale_of(mesh);
  return number(volume_m3 / (s.size_m * s.size_m * s.size_m)) + " " + s.name + "^3";
}

std::string describe_box(const Mesh& mesh, const Eigen::AlignedBox3d& box_m) {
  const Scale s = scale_of(mesh);
  // Nine digits: a box a few ulps of float32 thick is still two places.
  return "from " + triple(box_m.min(), s.size_m, 9) + " to " + triple(box_m.max(), s.size_m, 9) + " " + s.name;
}

std::string describe_triangle(const Mesh& mesh, std::size_t k) {
  std::string s = "triangle " + std::to_string(k);
  if (mesh.triangle_lines.size() == mesh.triangles.size() && k < mesh.triangle_lines.size()) {
    s += " (line " + std::to_string(mesh.triangle_lines[k]) + ")";
  }
  if (k < mesh.triangles.size()) {
    const Triangle& t = mesh.triangles[k];
    const std::size_t n = mesh.vertices.size();
    if (t[0] < n && t[1] < n && t[2] < n) {
      s += " at " + describe_point(mesh, (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0);
    }
  }
  return s;
}

}  // namespace poise::geometry
