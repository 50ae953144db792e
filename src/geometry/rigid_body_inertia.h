#pragma once
/// Rigid-body algebra of mass properties (mass, centre of mass, inertia tensor about the
/// centre of mass; SI): principal axes, moving a body, scaling it, and adding bodies.
///
///   placed at x -> R x + t:   c' = R c + t,  I' = R I R^T (the inertia about the centre of
///                             mass turns with the body and does not move with it)
///   scaled by s about its centre of mass, density unchanged:  m' = s^3 m,  I' = s^5 I
///   assembly (parallel-axis theorem):  m = sum m_i,  c = sum m_i c_i / m,
///       I = sum [ I_i + m_i (|d_i|^2 1 - d_i d_i^T) ],  d_i = c_i - c
#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <vector>

#include "geometry/mass_properties.h"

namespace poise::geometry {

/// Principal moments in ascending order and their axes: column k of `axes` is the unit axis
/// of moments[k]; the axes form a right-handed frame (det = +1). Each axis has its
/// largest-magnitude component positive, except the third when no two moments are equal
/// (then the handedness fixes it); two equal moments may be listed in either order.
struct PrincipalAxes {
  Eigen::Vector3d moments = Eigen::Vector3d::Zero();  ///< kg m^2
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
};
/// Eigen's self-adjoint eigensolver on the (symmetrized) inertia tensor.
PrincipalAxes principal_axes(const Eigen::Matrix3d& inertia);

/// The body moved rigidly: x -> pose * x.
MassProperties placed(const MassProperties& body, const Eigen::Isometry3d& pose);
/// The body scaled uniformly by s about its centre of mass (same density).
MassProperties scaled(const MassProperties& body, double s);
/// The assembly of bodies (parallel-axis theorem). An empty list gives zero mass.
MassProperties assemble(const std::vector<MassProperties>& bodies);

}  // namespace poise::geometry
