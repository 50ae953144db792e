#include "geometry/rigid_body_inertia.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <utility>

namespace poise::geometry {

PrincipalAxes principal_axes(const Eigen::Matrix3d& inertia) {
  const Eigen::Matrix3d sym = 0.5 * (inertia + inertia.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(sym);  // ascending eigenvalues
  PrincipalAxes p;
  p.moments = solver.eigenvalues();
  p.axes = solver.eigenvectors();
  for (int k = 0; k < 3; ++k) {
    Eigen::Index i;
    p.axes.col(k).cwiseAbs().maxCoeff(&i);
    if (p.axes(i, k) < 0.0) p.axes.col(k) *= -1.0;
  }
  if (p.axes.determinant() < 0.0) {
    // Two equal moments (a body of revolution): any basis of their plane is principal, so
    // swapping them makes the frame right-handed with every axis still pointing "forward".
    const double tol = 1e-9 * p.moments.cwiseAbs().maxCoeff();
    if (std::abs(p.moments[0] - p.moments[1]) <= tol) {
      p.axes.col(0).swap(p.axes.col(1));
      std::swap(p.moments[0], p.moments[1]);
    } else if (std::abs(p.moments[1] - p.moments[2]) <= tol) {
      p.axes.col(1).swap(p.axes.col(2));
      std::swap(p.moments[1], p.moments[2]);
    } else {
      p.axes.col(2) *= -1.0;
    }
  }
  return p;
}

MassProperties placed(const MassProperties& body, const Eigen::Isometry3d& pose) {
  MassProperties p;
  p.mass = body.mass;
  p.com = pose * body.com;
  p.inertia = pose.linear() * body.inertia * pose.linear().transpose();
  return p;
}

MassProperties scaled(const MassProperties& body, double s) {
  MassProperties p = body;
  const double s2 = s * s;
  p.mass *= s2 * s;
  p.inertia *= s2 * s2 * s;
  return p;
}

MassProperties assemble(const std::vector<MassProperties>& bodies) {
  MassProperties total;
  for (const auto& b : bodies) {
    total.mass += b.mass;
    total.com += b.mass * b.com;
  }
  if (total.mass == 0.0) return MassProperties{};
  total.com /= total.mass;
  for (const auto& b : bodies) {
    const Eigen::Vector3d d = b.com - total.com;
    total.inertia += b.inertia + b.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  return total;
}

}  // namespace poise::geometry
