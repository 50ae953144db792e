#pragma once
/// Triangles of a polygon face (an OBJ `f` with more than three vertices) by ear clipping:
/// the polygon is projected on the plane of its (Newell) normal, and a corner is cut off as a
/// triangle only when it turns the polygon's way with non-zero area and no other corner lies
/// in it. Unlike a fan from the first vertex, this makes no zero-area slivers where vertices
/// are collinear (a CAD edge split by a vertex of the neighbouring face) and no triangles
/// outside a concave polygon. The triangles keep the polygon's winding. When no corner can be
/// cut (a polygon whose remaining vertices are all collinear, or one that crosses itself) or
/// the work would grow past a bound, the rest is fanned as before: what that leaves without
/// area is judged by the mesh checks (geometry/mesh_needles.h).
#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "geometry/mesh.h"

namespace poise::geometry {

/// `polygon`: indices into `vertices`, in the face's order (at least three).
std::vector<Triangle> triangulate_polygon(const std::vector<Eigen::Vector3d>& vertices,
                                          const std::vector<std::uint32_t>& polygon);

}  // namespace poise::geometry
