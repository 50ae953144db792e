#include "geometry/part_assembly.h"

#include "core/error.h"
#include "geometry/rigid_body_inertia.h"

namespace poise::geometry {

AssemblyPart make_assembly_part(const std::string& name, const Mesh& mesh, double density,
                                const Eigen::Isometry3d& placement) {
  AssemblyPart p;
  p.name = name;
  p.density = density;
  p.placement = placement;
  p.unit_density = to_mass_properties(exact_moments(mesh, 1.0));
  require(p.unit_density.mass > 0.0, "make_assembly_part: the mesh of " + name + " has no positive volume");
  return p;
}

Eigen::Isometry3d as_built_pose(const AssemblyPart& part, const PartDeviation& d) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  const double angle = d.rotation.norm();
  const Eigen::Matrix3d dr =
      angle > 0.0 ? Eigen::AngleAxisd(angle, d.rotation / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
  pose.linear() = dr * part.placement.linear();
  pose.translation() = part.placement.translation() + d.translation;
  return pose;
}

MassProperties as_built_part(const AssemblyPart& part, const PartDeviation& d) {
  const double density = part.density + d.density;
  require(density > 0.0, "as_built_part: the density of " + part.name + " as drawn is not positive");
  require(1.0 + d.scale > 0.0, "as_built_part: the scale of " + part.name + " as drawn is not positive");
  MassProperties body = scaled(part.unit_density, 1.0 + d.scale);  // about its centre of mass
  body.mass *= density;
  body.inertia *= density;
  return placed(body, as_built_pose(part, d));
}

MassProperties as_built_assembly(const std::vector<AssemblyPart>& parts, const std::vector<PartDeviation>& deviations) {
  POISE_INVARIANT(deviations.empty() || deviations.size() == parts.size(),
                  "as_built_assembly: one deviation per part, or none");
  std::vector<MassProperties> bodies;
  bodies.reserve(parts.size());
  for (std::size_t i = 0; i < parts.size(); ++i) {
    bodies.push_back(as_built_part(parts[i], deviations.empty() ? PartDeviation{} : deviations[i]));
  }
  return assemble(bodies);
}

Eigen::Vector3d static_unbalance(const MassProperties& body, const Eigen::Vector3d& point,
                                 const Eigen::Vector3d& direction) {
  const Eigen::Vector3d a = direction.normalized();
  const Eigen::Vector3d r = body.com - point;
  return body.mass * (r - a * a.dot(r));
}

}  // namespace poise::geometry
