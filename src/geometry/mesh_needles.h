#pragma once
/// Zero-area triangles ("needles"): three collinear vertices, or a repeated one. CAD exports
/// make them (an OpenSCAD STL with two exactly collinear triangles lying back to back, an OBJ
/// polygon fanned through collinear vertices). They enclose nothing, so a closed part is
/// refused only if its surface needs them to be closed and they are not part of it.
///
/// A set of needles the surface does not need is one whose edges pair up among themselves
/// (as often one way as the other): removing it leaves every other edge paired as it was, so
/// a closed surface stays closed and its volume is unchanged. drop_needles() removes the
/// largest such set it finds (needles on an edge that does not pair up are kept, then their
/// neighbours are judged again). A needle that closes the surface (filling a T-junction: a
/// vertex lying on another triangle's edge) is kept; check_mesh() accepts it when the whole
/// surface is closed, as it adds no volume.
#include <cstddef>
#include <string>
#include <vector>

#include "geometry/mesh.h"

namespace poise::geometry {

/// Whether triangle k has zero area: a repeated vertex, or twice its area at most 1e-12 of
/// its longest edge squared (collinear to rounding).
bool zero_area(const Mesh& mesh, std::size_t k);

/// The zero-area triangles the surface does not need (see above), ascending.
std::vector<std::size_t> unneeded_needles(const Mesh& mesh);

struct NeedleReport {
  std::size_t dropped = 0;
  std::string first;  ///< the first dropped, as describe_triangle() named it ("" if none)
};

/// Removes unneeded_needles(mesh) and says how many and which came first.
NeedleReport drop_needles(Mesh& mesh);

}  // namespace poise::geometry
