#pragma once
/// How wide the gaps of an open surface are: what tells a crack of a few float32 ulps (which a
/// weld closes, geometry/mesh_weld.h) from a missing face (which it does not).
///
/// Across a gap, an open edge faces another open edge. The width of the gap at an open edge
/// is its distance to the nearest other open edge, measured from the farther of its two ends
/// (so an edge sharing one end with it still counts by its other end: the two sides of a
/// crack that meet at a vertex). The widest gap is the largest of those widths: the size of a
/// crack (a weld of that size joins its sides), the size of a hole (a missing triangle's
/// height).
#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

#include "geometry/mesh.h"

namespace poise::geometry {

using Edge = std::array<std::uint32_t, 2>;

struct Gap {
  double width_m = -1.0;                            ///< < 0: no other open edge to measure to
  Eigen::Vector3d where = Eigen::Vector3d::Zero();  ///< the middle of the open edge at the widest gap
};

/// The widest gap between the open edges given (vertex pairs of `mesh`). Bounded work: past
/// some 2e7 edge-to-edge distances the edges not yet looked at are left out.
Gap widest_gap(const Mesh& mesh, const std::vector<Edge>& open_edges);

}  // namespace poise::geometry
