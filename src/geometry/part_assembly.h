#pragma once
/// An assembly of a designer's parts (meshes from CAD) as built: each part's mass properties
/// computed once, exactly, from its mesh at unit density, then moved through one sample's
/// deviations in closed form (rigid_body_inertia.h), so a Monte Carlo sample costs O(parts):
///
///   part frame -> assembly:   x_asm = t + dt + R(dtheta) R0 (c + s (x - c))
///     R0, t      the nominal placement (rotation, translation)
///     dt         placement error, assembly axes (m)
///     dtheta     small rotation error about the assembly's x, y, z at the placed part origin
///                (rad; applied as the rotation vector dtheta, exact for any size)
///     s = 1 + e  uniform scale about the part's own centre of mass c (a part made e too large
///                grows about its centre; it does not move)
///     rho + drho density
///   so  m = (rho + drho) s^3 V,   c_asm = t + dt + R c,   I = (rho + drho) s^5 R I_1 R^T,
///   R = R(dtheta) R0, V and I_1 the mesh's volume and inertia at unit density (about c).
#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "geometry/mass_properties.h"
#include "geometry/mesh.h"

namespace poise::geometry {

struct AssemblyPart {
  std::string name;
  double density = 0.0;                                         ///< kg/m^3, nominal
  Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();  ///< part frame -> assembly
  MassProperties unit_density;  ///< of the mesh in the part's frame at 1 kg/m^3 (mass = volume, m^3)
};

/// A part from its checked mesh (exact_moments at unit density). The mesh is not kept.
AssemblyPart make_assembly_part(const std::string& name, const Mesh& mesh, double density,
                                const Eigen::Isometry3d& placement);

/// One sample's deviations of one part from its drawing (zero: as drawn).
struct PartDeviation {
  double density = 0.0;                                   ///< kg/m^3, added to the nominal
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();  ///< m, assembly axes
  Eigen::Vector3d rotation = Eigen::Vector3d::Zero();     ///< rad, rotation vector, assembly axes
  double scale = 0.0;                                     ///< relative size error e (s = 1 + e)
};

/// The part's pose as built: translation t + dt, rotation R(dtheta) R0.
Eigen::Isometry3d as_built_pose(const AssemblyPart& part, const PartDeviation& d);
/// The part as built, in assembly coordinates.
MassProperties as_built_part(const AssemblyPart& part, const PartDeviation& d);
/// The assembly as built: the parts' sum by the parallel-axis theorem. deviations: one per
/// part (same order), or empty for the nominal assembly.
MassProperties as_built_assembly(const std::vector<AssemblyPart>& parts, const std::vector<PartDeviation>& deviations);

/// Static unbalance about an axis through `point` along `direction` (any length): the mass
/// times the offset of the centre of mass from the axis, as a vector perpendicular to the
/// axis (kg m); its norm is U = m e.
Eigen::Vector3d static_unbalance(const MassProperties& body, const Eigen::Vector3d& point,
                                 const Eigen::Vector3d& direction);

}  // namespace poise::geometry
