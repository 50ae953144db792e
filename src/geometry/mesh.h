#pragma once
/// Triangle meshes of parts and assemblies (SI units, metres).
///
/// A part is one or more closed shells. Orientation carries meaning: a shell whose
/// triangles wind counter-clockwise seen from outside (outward normals) adds material, an
/// inverted shell removes it, so "disk minus hole" is the disk's shell plus the hole's
/// cylinder inverted. Every integral of Poise over a mesh is an integral of f(x) w(x), with
/// w the winding number of the shells about x (1 inside material, 0 outside, 0 in a hole),
/// which is what both the ray-cast integration and the divergence-theorem formula compute.
#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace poise::geometry {

using Triangle = std::array<std::uint32_t, 3>;

struct Mesh {
  std::string name;
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Triangle> triangles;
  /// Line of the file each triangle came from (OBJ face, ASCII STL facet); empty when the
  /// mesh was generated or read from binary STL. Messages about a triangle name its line.
  std::vector<std::size_t> triangle_lines;
  /// Metres per length unit of the file the mesh was read from (set by the loaders): messages
  /// give coordinates and sizes in that unit (geometry/mesh_text.h). 1 for a generated mesh.
  double unit_m = 1.0;

  /// Appends another mesh's vertices and triangles (indices shifted).
  void append(const Mesh& other);
  /// Reverses every triangle's winding (material <-> cavity).
  void flip();
  /// x -> R x + t for every vertex.
  void transform(const Eigen::Isometry3d& pose);
  /// Outward (unnormalized, twice the area) normal of triangle k: (b - a) x (c - a).
  Eigen::Vector3d face_normal(std::size_t k) const;
  Eigen::AlignedBox3d bounds() const;
};

/// Checks that the mesh is closed and consistently oriented: every directed edge (a, b)
/// has exactly one partner (b, a). Returns "" if so, else what is wrong, naming a triangle
/// and its edge, e.g. "triangle 12: edge (4, 9) has no opposite edge (the mesh is open)".
std::string check_closed(const Mesh& mesh);

/// Removes triangles with repeated vertex indices (zero area by construction).
void remove_degenerate(Mesh& mesh);

/// Removes the triangles whose indices are listed (ascending), with their file lines.
void remove_triangles(Mesh& mesh, const std::vector<std::size_t>& ascending);

}  // namespace poise::geometry
