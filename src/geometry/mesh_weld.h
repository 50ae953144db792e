#pragma once
/// Welding of a mesh's vertices closer than a tolerance: what a CAD export leaves as cracks
/// (a SolidWorks STL whose shared edges differ by 1-3 float32 ulps) or never shares at all (an
/// OBJ that gives every triangle its own three vertices). Without it such a closed part is
/// refused as open. Vertices are taken in file order; each is merged into the first kept vertex
/// within the tolerance in every coordinate (a grid of cells of the tolerance's size, the 27
/// around each vertex searched), so the result does not depend on anything but the file.
/// Triangles that welding leaves with a repeated vertex (slivers narrower than the tolerance)
/// are dropped: they enclose nothing.
#include <cstddef>

#include "geometry/mesh.h"

namespace poise::geometry {

/// The default tolerance, relative to the diagonal of the part's bounding box: 1e-6 (0.1 um
/// on a 100 mm part, some 10 float32 ulps of its coordinates; far below any feature).
inline constexpr double kWeldRelative = 1e-6;

struct WeldReport {
  double tolerance_m = 0.0;
  std::size_t merged_vertices = 0;    ///< vertices merged into another
  std::size_t dropped_triangles = 0;  ///< triangles left with a repeated vertex
};

/// Welds the vertices of `mesh` within `tolerance_m` (<= 0: none) and removes unused ones.
WeldReport weld_vertices(Mesh& mesh, double tolerance_m);

/// The default tolerance of a mesh: kWeldRelative times its bounding box's diagonal.
double default_weld_tolerance(const Mesh& mesh);

}  // namespace poise::geometry
