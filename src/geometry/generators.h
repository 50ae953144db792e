#pragma once
/// Parametric meshes of the parts Poise studies (SI units, closed and outward-oriented;
/// holes are inverted shells, see mesh.h).
///
///   revolve()          a closed profile (a, r) turned about the local z axis: cylinders,
///                      tubes, the seeker housing with its window opening, the window
///   box()              an axis-aligned box, faces subdivided (for clearance queries)
///   simulator_disk()   the rotor disk of the gimbal test simulator (Yang 2015, Sec. 6): two
///                      circles of mounting holes (C_A r = 5.10 cm, C_B r = 3.50 cm, eight
///                      each), clump weights in chosen holes, and as-built deviations (hole
///                      positions, thickness, face wedge)
///   seeker_*()         the two-axis seeker of Wang 2011: a rectangular yaw ring whose height
///                      follows the yaw bearing span L1 and width the pitch span L2, the pitch
///                      assembly (optical barrel and pitch shafts), the housing (a cylinder
///                      about the roll axis x with a front wall, the window opening and the
///                      yaw-bearing posts) and the window.
/// Polygons of `segments` sides replace circles with the same area (radius scaled by
/// sqrt((2 pi / n) / sin(2 pi / n))), so masses match the drawing's to O(n^-4).
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "geometry/mesh.h"

namespace poise::geometry {

/// A solid of one material. An inverted mesh (a hole) has negative volume: with the parent's
/// density it removes that material.
struct Body {
  Mesh mesh;
  double density = 0.0;  ///< kg/m^3
};
using Assembly = std::vector<Body>;
/// All bodies' meshes in one (for export and ray tracing).
Mesh merge(const Assembly& parts, const std::string& name);

/// Radius of the n-gon with the area of the circle of radius r.
double equal_area_radius(double r, int segments);

/// Turns the closed polygon `profile` of points (a, r), r >= 0, about the z axis of `frame`
/// (a along z). Either orientation of the profile is accepted; the mesh is outward.
/// Points with r = 0 become one vertex on the axis.
Mesh revolve(const std::vector<Eigen::Vector2d>& profile, int segments, const std::string& name,
             const Eigen::Isometry3d& frame = Eigen::Isometry3d::Identity());
/// Solid cylinder of radius r (equal-area polygon) about the z axis of `frame`, z in [z0, z1].
Mesh cylinder(double r, double z0, double z1, int segments, const std::string& name,
              const Eigen::Isometry3d& frame = Eigen::Isometry3d::Identity());
/// Tube r_in..r_out about z, z in [z0, z1].
Mesh tube(double r_in, double r_out, double z0, double z1, int segments, const std::string& name,
          const Eigen::Isometry3d& frame = Eigen::Isometry3d::Identity());
/// Box [lo, hi], each face an n x n grid of quads.
Mesh box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int subdivisions, const std::string& name);

// ---- the simulator disk -----------------------------------------------------------------

struct DiskHole {
  double radius = 0.0;    ///< of its centre from the disk axis (m)
  double angle = 0.0;     ///< rad, from the disk's x axis
  double diameter = 0.0;  ///< m
};

/// A clump weight: a cylinder of `diameter` and `mass` (screw, washers and nut lumped)
/// standing on the disk's top face (z = thickness), centred on its hole.
struct DiskClump {
  std::size_t hole = 0;   ///< index into DiskSpec::holes
  double mass = 0.0;      ///< kg
  double density = 0.0;   ///< kg/m^3
  double diameter = 0.0;  ///< m
};

struct DiskSpec {
  double radius = 0.0;     ///< m
  double thickness = 0.0;  ///< m, at the centre
  double density = 0.0;    ///< kg/m^3
  /// Face parallelism: the top face tilts so that the thickness differs by `wedge` (m)
  /// across the diameter, thickest towards `wedge_angle`.
  double wedge = 0.0;
  double wedge_angle = 0.0;
  std::vector<DiskHole> holes;
  std::vector<DiskClump> clumps;
  int segments = 256;      ///< of the rim
  int hole_segments = 48;  ///< of each hole and clump
};

/// Eight holes on each of the two circles C_A (5.10 cm) and C_B (3.50 cm), circle A from
/// 0 deg, circle B turned by `b_offset`, all of diameter d.
std::vector<DiskHole> yang2015_hole_pattern(double d, double b_offset, double r_a = 0.051, double r_b = 0.035);

/// Disk (material) + one inverted cylinder per hole + one body per clump. The disk's top face
/// is z = thickness + wedge/(2R) (x cos a + y sin a), the bottom z = 0; hole shells share
/// those planes so the holes are exactly through.
Assembly simulator_disk(const DiskSpec& spec);

// ---- the two-axis seeker ----------------------------------------------------------------

/// Dimensions of the seeker's frames and housing (m). The frames follow the bearing spans.
/// Axes: x the roll axis (LOS at zero), z the yaw axis, the pitch axis along y; the gimbal
/// centre is the origin.
struct SeekerGeometry {
  double yaw_span = 0.082;       ///< L1: yaw bearings at z = +-L1/2 (in the housing's posts)
  double pitch_span = 0.056;     ///< L2: pitch bearings at y = +-L2/2 (in the ring's sides)
  double bearing_width = 0.007;  ///< each bearing's width (m)
  double ring_section = 0.006;   ///< ring members' thickness (radial)
  double ring_depth = 0.020;     ///< ring extent along x
  double ring_gap = 0.001;       ///< ring top/bottom members to the yaw bearing seats
  double shaft_radius = 0.005;   ///< yaw and pitch shafts (short journals in the bearings)
  double barrel_radius = 0.020;  ///< optical barrel, outer
  double barrel_wall = 0.002;
  double barrel_back = -0.030;  ///< x of the barrel's ends, pitch frame
  double barrel_front = 0.040;
  double aperture_radius = 0.015;  ///< clear aperture of the optics (beam radius)
  double detector_x = -0.025;      ///< beam origin plane, pitch frame
  double housing_radius = 0.058;   ///< inner radius of the housing cylinder
  double housing_wall = 0.003;
  double housing_back = -0.080;  ///< x of the open back end
  double front_x = 0.075;        ///< x of the front wall's inner face
  double front_wall = 0.004;
  double window_radius = 0.055;  ///< radius of the window opening in the front wall
  double post_radius = 0.010;    ///< yaw bearing posts (cylinders about z, housing to bearing)
  int segments = 96;
};

/// The seeker's parts. Moving: `ring` (yaw frame), `barrel` and `pitch_shafts` (pitch frame),
/// each in its own frame's coordinates; fixed, base coordinates: `housing` (cylinder and front
/// wall with the window opening), `posts` (the yaw-bearing posts), `window` (glass in the
/// opening: a beam ray that reaches it first leaves the seeker).
struct SeekerMeshes {
  Mesh ring, barrel, pitch_shafts, housing, posts, window;
};
SeekerMeshes seeker_meshes(const SeekerGeometry& g);
/// "" if the parts can be built, else what is wrong (e.g. the aperture wider than the bore).
/// Frames that collide are not refused: their clearance comes out negative.
std::string check_seeker_geometry(const SeekerGeometry& g);

}  // namespace poise::geometry
