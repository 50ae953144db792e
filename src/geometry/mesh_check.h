#pragma once
/// Checking a mesh before its mass properties are trusted (a designer's STL/OBJ export).
///
/// The divergence theorem and the ray-cast integration (mass_properties.h) both integrate
/// over the region of winding number 1, which is the part only when the surface is closed,
/// two-manifold and consistently oriented. check_mesh() finds what breaks that:
///   open edge           an edge of one triangle only (a hole in the surface)
///   non-manifold edge   an edge of three or more triangles that do not run it as often in
///                       each direction (two closed solids touching along an edge do: those
///                       edges are counted as shared_edges and accepted)
///   inconsistent        triangles wound against their neighbours (an edge both its
///     orientation       triangles run the same way): the minority of the shell is flipped
///   degenerate          a triangle with a repeated vertex, or of zero area (collinear
///     triangle          vertices, area below 1e-12 of its longest edge squared) in a surface
///                       that is not closed. In a closed surface a zero-area triangle fills a
///                       T-junction (a vertex on another triangle's edge) and adds no volume:
///                       it is counted (zero_area_triangles), not refused; load_mesh() has
///                       already dropped those the surface does not need (mesh_needles.h)
///   shells              connected components (triangles sharing an edge) and their signed
///                       volumes: one of negative volume is inside out, unless it lies inside
///                       another shell (the wall of an internal cavity, which removes material)
/// Several closed shells in one file are one part (a screw and its washer, a frame in pieces).
/// Shells that overlap (two solids exported into one another) are not found here: the ray
/// cast finds them (RayCastStats::overlap_rays, mass_properties.h).
/// Messages give places in the file's unit (geometry/mesh_text.h) and the width of the widest
/// gap of an open surface (geometry/mesh_gaps.h).
#include <cstddef>
#include <string>
#include <vector>

#include "core/error.h"
#include "geometry/mesh.h"
#include "geometry/mesh_text.h"

namespace poise::geometry {

/// A mesh refused by check_mesh(); what() names the file, what is wrong and where.
class MeshCheckError : public Error {
 public:
  using Error::Error;
};

/// One connected component of the surface.
struct Shell {
  std::size_t first_triangle = 0;  ///< lowest triangle index of the shell
  std::size_t triangles = 0;
  double volume_m3 = 0.0;  ///< signed: positive when its normals point outwards
  bool cavity = false;     ///< negative volume, inside another shell: an internal void
};

/// A count of one kind of defect and the first triangle that shows it.
struct Defect {
  std::size_t count = 0;
  std::size_t first_triangle = 0;
};

struct MeshCheck {
  Defect open_edges, non_manifold_edges, degenerate_triangles;
  /// Zero-area triangles with three distinct vertices. Degenerate (and counted there too)
  /// when the surface is not closed; accepted when it is (they fill T-junctions).
  Defect zero_area_triangles;
  /// Triangles that repeat another with the same three vertices in the same winding: a face
  /// (or a whole shell) exported twice, whose volume the divergence theorem would count twice.
  /// (The same face wound the other way is two bodies touching, not a duplicate.)
  Defect duplicate_triangles;
  /// Edges of four or more triangles, run as often each way: closed solids touching along an
  /// edge or a face (bodies exported together). Not an error: the surface bounds a region.
  Defect shared_edges;
  /// Triangles whose winding disagrees with the majority of their shell (found by walking
  /// the shell across its two-triangle edges); shells where no consistent winding exists.
  Defect flipped_triangles, non_orientable_shells;  ///< "shells" here: patches joined by two-triangle edges
  std::vector<Shell> shells;                        ///< in order of their first triangle
  double volume_m3 = 0.0;                           ///< sum of the shells' signed volumes
  /// One sentence per defect, each starting "<mesh name>: ", e.g.
  /// "disk.stl: not closed: 3 open edges, the first at triangle 1799 (line 12596) at
  /// (12.5, -3, 40) mm; the widest gap is 0.5 mm across, near (12, -3, 40) mm".
  std::vector<std::string> errors;
  bool ok() const { return errors.empty(); }
};

/// Checks topology, orientation, degeneracy and shells. Never throws on a bad mesh.
MeshCheck check_mesh(const Mesh& mesh);

/// Removes every triangle that repeats an earlier one (same vertices, same winding); returns
/// how many (the `--drop-duplicates` of poise mass-properties).
std::size_t drop_duplicate_triangles(Mesh& mesh);

/// check_mesh(), throwing MeshCheckError with every error (one per line) if any.
MeshCheck require_valid_mesh(const Mesh& mesh);

/// A warning when the part's size suggests the wrong --unit: its largest bounding-box side
/// above 5 m or below 0.5 mm, with what the numbers would mean in the other units
/// ("disk.stl: 60 m across with --unit m: is the file in mm (60 mm)?"). "" if plausible.
/// `unit` is the name the lengths were read in ("mm", "m", "in", "cm"), `unit_m` its size.
std::string unit_warning(const Mesh& mesh, const std::string& unit, double unit_m);

}  // namespace poise::geometry
