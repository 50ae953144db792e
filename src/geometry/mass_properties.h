#pragma once
/// Mass, centre of mass and inertia tensor of meshes and assemblies, two independent ways:
///
/// 1. Ray-cast integration (the method that scales to any mesh, with Embree): a grid of
///    parallel rays along one axis, spacing h, one ray per cell centre; along each ray every
///    surface crossing is found (Embree, all hits) and refined in double precision; the
///    winding number w(t) (+1 entering, -1 leaving) weights the segments between crossings,
///    and each segment is integrated exactly: for p(t) = o + t d on [t0, t1],
///      int 1 dt = L,  int p dt = o L + d (t1^2 - t0^2)/2,
///      int p p^T dt = o o^T L + (o d^T + d o^T)(t1^2 - t0^2)/2 + d d^T (t1^3 - t0^3)/3.
///    The only approximation is the midpoint rule across the rays (error O(h^2) where the
///    surface is smooth, O(h^1.5) relative from cells cut by the silhouette).
/// 2. The divergence theorem on a closed mesh (exact for the polyhedron): each triangle
///    (a, b, c) with the origin spans a signed tetrahedron, V = a.(b x c)/6,
///      int x dV = V (a + b + c)/4,  int x x^T dV = V/20 (a a^T + b b^T + c c^T + s s^T), s = a+b+c
///    (the covariance of a tetrahedron, Tonon 2004; the same sums as Mirtich 1996's).
/// Both compute int rho w(x) f(x) dV, so an inverted shell (a hole) subtracts.
///
/// Inertia tensor: I = int rho (|r|^2 1 - r r^T) dV about the centre of mass.
#include <Eigen/Dense>
#include <vector>

#include "geometry/embree_scene.h"
#include "geometry/generators.h"
#include "geometry/mesh.h"

namespace poise::geometry {

/// Zeroth, first and second moments about the origin; additive over bodies.
struct Moments {
  double mass = 0.0;                                 ///< kg
  Eigen::Vector3d first = Eigen::Vector3d::Zero();   ///< kg m
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  ///< kg m^2, int rho x x^T
  Moments& operator+=(const Moments& o);
};

struct MassProperties {
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  ///< about the centre of mass, kg m^2
};
MassProperties to_mass_properties(const Moments& m);

/// Divergence-theorem moments of a closed mesh of uniform density.
Moments exact_moments(const Mesh& mesh, double density);
Moments exact_moments(const Assembly& parts);

struct RayGridOptions {
  int axis = 2;  ///< rays along x (0), y (1) or z (2)
  /// Cells across the larger transverse side of the body's bounding box; h = that side / n.
  int rays_per_side = 200;
};

struct RayCastStats {
  std::size_t rays = 0;       ///< cast
  std::size_t crossings = 0;  ///< surface crossings found
  std::size_t open_rays = 0;  ///< rays whose winding did not return to 0 (mesh not closed)
  /// Rays that pass through material of winding 2 or more over a non-zero length: shells of
  /// one mesh that overlap (their common material would count twice).
  std::size_t overlap_rays = 0;
  /// What those rays count more than once: each segment of winding w >= 2 adds (w - 1) times
  /// its length times the ray's cell area (h^2). An estimate of the overlap's volume (the rays
  /// sample it; an overlap thinner than the rays' spacing may be missed or over-weighted).
  double overlap_volume_m3 = 0.0;
  /// Where: the box of those segments, each widened by half a cell across; empty if none.
  Eigen::AlignedBox3d overlap_box;
  RayCastStats& operator+=(const RayCastStats& o);
};

/// Overlapping shells (RayCastStats::overlap_volume_m3) are accepted up to this share of the
/// part's volume by default: the facets of touching curved faces cross by their chord error
/// (5e-8 of a part measured), solids exported into one another overlap by far more.
inline constexpr double kMaxOverlapShare = 1e-6;

/// Ray-cast moments of every mesh of a scene built with collect_all_hits (densities per
/// geomID). Rows of the grid run in parallel (oneTBB); the sum is taken in row order, so
/// the result is the same for any thread count.
Moments raycast_moments(const EmbreeScene& scene, const std::vector<double>& densities, const RayGridOptions& opt,
                        RayCastStats* stats = nullptr);
/// One scene and one grid per body (fitted to its bounding box), so a small part (a hole, a
/// clump weight) gets as many rays as a large one and its result moves with it exactly.
Moments raycast_moments(const Assembly& parts, const RayGridOptions& opt, RayCastStats* stats = nullptr);

/// Closed forms used as references (about the centre of mass).
MassProperties solid_cylinder_z(double mass, double radius, double length);
MassProperties solid_box(double mass, const Eigen::Vector3d& size);

}  // namespace poise::geometry
