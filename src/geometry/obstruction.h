#pragma once
/// The optical beam of a two-axis seeker through its own frames and housing, and the
/// clearance between the moving frames and the housing, at one gimbal pose.
///
/// Beam: `rays` parallel rays along the optical axis l (pitch frame, with the collimation
/// error of the sample), their origins on the detector plane x = detector_x spread evenly
/// over the clear aperture (a Vogel sunflower: ray i at radius a sqrt((i + 1/2)/N), angle
/// i times the golden angle, equal area per ray). Each ray is traced (Embree, packets of 16)
/// in the frame of each scene, rigidly transformed: base (housing, posts, window), yaw
/// (ring), pitch (barrel, shafts). A ray is unobstructed when the first surface it meets is
/// the window; the unobstructed fraction is their share.
///
/// Clearance between two parts: the least distance from each part's vertices to the other
/// part's triangles (Embree rtcPointQuery with an exact closest-point-on-triangle callback),
/// both ways, negative when a vertex lies inside the other part (interference: minus its
/// depth). Exact at the vertices; the meshes are subdivided so the vertex spacing bounds
/// what lies between them.
#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "geometry/embree_scene.h"
#include "geometry/generators.h"
#include "models/seeker_los_chain.h"

namespace poise::geometry {

/// Orientation of the yaw frame in the base and of the pitch frame in the yaw frame, and
/// the optical axis in the pitch frame. The frames turn about the gimbal centre.
struct GimbalPose {
  Eigen::Matrix3d yaw = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d pitch = Eigen::Matrix3d::Identity();
  Eigen::Vector3d optical_axis = Eigen::Vector3d::UnitX();
};

/// The exact kinematic chain of models/seeker_los_chain.h at (alpha, beta): axis tilts and
/// run-out of the sample turn the frames, collimation turns the optical axis.
GimbalPose seeker_pose(const models::SeekerErrorState& errors, double alpha, double beta);

/// Nominal pose (no errors).
GimbalPose nominal_pose(double alpha, double beta);

/// The seeker's scenes, built once (immutable; trace from any thread).
class SeekerScenes {
 public:
  SeekerScenes(const SeekerGeometry& g, int beam_rays);
  /// With the parts given (a designer's meshes for some of them, each closed and checked): the
  /// beam's origins and aperture still come from `g` (detector_x, aperture_radius).
  SeekerScenes(const SeekerGeometry& g, SeekerMeshes parts, int beam_rays);
  const SeekerGeometry& geometry() const { return geometry_; }
  const SeekerMeshes& meshes() const { return meshes_; }
  /// Beam ray origins in the pitch frame (x = detector_x).
  const std::vector<Eigen::Vector3d>& beam_origins() const { return origins_; }

  struct Beam {
    std::size_t rays = 0, unobstructed = 0;
    double fraction() const { return rays ? static_cast<double>(unobstructed) / static_cast<double>(rays) : 0.0; }
  };
  Beam trace_beam(const GimbalPose& pose) const;

  /// Clearances (m) at a pose; negative = interference.
  struct Clearance {
    double ring_housing = 0.0;    ///< yaw ring to housing (cylinder and front wall)
    double barrel_housing = 0.0;  ///< optical barrel to housing
    double barrel_ring = 0.0;     ///< barrel to yaw ring (the pitch motion inside the ring)
    double min() const { return std::min({ring_housing, barrel_housing, barrel_ring}); }
  };
  Clearance clearance(const GimbalPose& pose) const;

 private:
  SeekerGeometry geometry_;
  SeekerMeshes meshes_;
  std::unique_ptr<EmbreeScene> base_, yaw_, pitch_;             // beam tracing (nearest hit)
  std::unique_ptr<EmbreeScene> housing_q_, ring_q_, barrel_q_;  // point queries, inside tests
  std::vector<Eigen::Vector3d> origins_;
};

/// Signed distance from the vertices of `a` (moved by `a_to_b` into b's frame) to the
/// closed mesh of scene `b` (built with collect_all_hits): the least distance, negative
/// (minus the depth) if a vertex is inside b.
double min_signed_distance(const Mesh& a, const Eigen::Isometry3d& a_to_b, const EmbreeScene& b);

/// Closest point on triangle (a, b, c) to p (Ericson, Real-Time Collision Detection 5.1.5).
/// `on_face` tells whether it lies inside the face (not on an edge or vertex).
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c, bool* on_face = nullptr);

}  // namespace poise::geometry
