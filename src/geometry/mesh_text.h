#pragma once
/// How messages about a mesh name its places and sizes: in the length unit of the file it was
/// read from (Mesh::unit_m: "mm" for a mm export), so a designer finds them in CAD as written.
///   describe_triangle  "triangle 1799 (line 12596) at (12.5, -3, 40) mm" (its centroid)
///   describe_point     "(12.5, -3, 40) mm"
///   describe_length    "0.00012 mm"
///   describe_volume    "0.0023 mm^3"
///   describe_box       "from (0, 0, 0) to (10, 4, 2) mm"
#include <Eigen/Geometry>
#include <cstddef>
#include <string>

#include "geometry/mesh.h"

namespace poise::geometry {

/// The name of a file unit: "mm", "cm", "m" or "in"; "" for any other size.
std::string unit_name(double unit_m);

std::string describe_point(const Mesh& mesh, const Eigen::Vector3d& p_m);
std::string describe_length(const Mesh& mesh, double length_m);
std::string describe_volume(const Mesh& mesh, double volume_m3);
std::string describe_box(const Mesh& mesh, const Eigen::AlignedBox3d& box_m);

/// "triangle 1799", with its file line when the mesh knows it ("triangle 1799 (line 12596)"),
/// then where it is: " at (x, y, z) mm", its centroid in the file's unit.
std::string describe_triangle(const Mesh& mesh, std::size_t k);

}  // namespace poise::geometry
