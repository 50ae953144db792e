// Mass properties against closed forms (a disk with an off-centre hole, a box, a faceted
// cylinder), moved and turned (R I R^T, parallel axis), scaled, and assembled.
#include <gtest/gtest.h>

#include <numbers>

#include "closed_form_meshes.h"
#include "geometry/generators.h"
#include "geometry/mass_properties.h"
#include "geometry/rigid_body_inertia.h"

namespace poise::geometry {
namespace {

void expect_same(const MassProperties& a, const MassProperties& b, double rel) {
  EXPECT_NEAR(a.mass, b.mass, rel * std::abs(b.mass));
  const double size = std::sqrt(b.inertia.norm() / std::abs(b.mass));  // a length of the body
  EXPECT_LE((a.com - b.com).norm(), rel * size) << a.com.transpose() << " vs " << b.com.transpose();
  EXPECT_LE((a.inertia - b.inertia).norm(), rel * b.inertia.norm()) << a.inertia << "\nvs\n" << b.inertia;
}

MassProperties exact(const Mesh& m, double rho) { return to_mass_properties(exact_moments(m, rho)); }

TEST(ClosedForms, DiskWithOffCentreHole) {
  const double R = 0.060, rh = 0.011, cx = 0.025, t = 0.012, rho = 2700;
  const int n = 72;
  const MassProperties ref = test::disk_with_offset_hole_closed_form(R, rh, cx, t, n, rho);
  expect_same(exact(test::disk_with_offset_hole(R, rh, cx, t, n), rho), ref, 1e-12);
  EXPECT_LT(ref.com.x(), 0.0);  // away from the hole
  // The polygon tends to the drawing's circles as O(n^-2).
  const double pi = std::numbers::pi, mc = rho * t * pi * (R * R - rh * rh);
  EXPECT_NEAR(ref.mass, mc, 2.0 * pi * pi / (3.0 * n * n) * mc);
  EXPECT_NEAR(ref.com.x(), -rh * rh * cx / (R * R - rh * rh), 1e-3 * cx);
  // The ray-cast integration agrees to its grid's O(h^2).
  RayGridOptions grid;
  grid.rays_per_side = 300;
  expect_same(to_mass_properties(raycast_moments({{test::disk_with_offset_hole(R, rh, cx, t, n), rho}}, grid)), ref,
              2e-3);
}

TEST(ClosedForms, BoxAndFacetedCylinder) {
  const Eigen::Vector3d lo(-0.01, 0.02, 0.0), hi(0.03, 0.05, 0.01);
  MassProperties b = solid_box(7850 * 0.04 * 0.03 * 0.01, hi - lo);
  b.com = 0.5 * (lo + hi);
  expect_same(exact(box(lo, hi, 3, "box"), 7850), b, 1e-12);
  // generators::cylinder's rim is the n-gon of the circle's area: its own closed form.
  const int n = 40;
  const double r = 0.02, rp = equal_area_radius(r, n);
  expect_same(exact(cylinder(r, -0.01, 0.03, n, "cyl"), 2700), test::ngon_prism_closed_form(rp, n, -0.01, 0.03, 2700),
              1e-12);
  EXPECT_NEAR(test::ngon_area(rp, n), std::numbers::pi * r * r, 1e-15);
}

TEST(RigidBodyInertia, PlacementRotatesAndMovesAsTheMesh) {
  const Mesh part = test::disk_with_offset_hole(0.05, 0.01, 0.02, 0.01, 48);
  const MassProperties body = exact(part, 2700);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(-0.3, Eigen::Vector3d::UnitX()))
                      .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.1, -0.05, 0.2);
  Mesh moved = part;
  moved.transform(pose);
  const MassProperties by_mesh = exact(moved, 2700), by_algebra = placed(body, pose);
  expect_same(by_algebra, by_mesh, 1e-11);
  // R I R^T written out, and the centre R c + t.
  const Eigen::Matrix3d r = pose.linear();
  EXPECT_LE((by_mesh.inertia - r * body.inertia * r.transpose()).norm(), 1e-11 * body.inertia.norm());
  EXPECT_LE((by_mesh.com - (r * body.com + pose.translation())).norm(), 1e-14);
  // Off-diagonal terms appear once the hole is turned away from the axes.
  EXPECT_GT(std::abs(by_mesh.inertia(0, 1)), 1e-3 * by_mesh.inertia.norm());
}

TEST(RigidBodyInertia, ScaleAboutTheCentreOfMass) {
  const Mesh part = test::disk_with_offset_hole(0.05, 0.01, 0.02, 0.01, 48);
  const MassProperties body = exact(part, 2700);
  const double s = 1.003;
  Mesh big = part;
  for (auto& v : big.vertices) v = body.com + s * (v - body.com);
  expect_same(scaled(body, s), exact(big, 2700), 1e-12);
}

TEST(RigidBodyInertia, AssemblyIsTheSumOfItsParts) {
  const Mesh a = test::disk_with_offset_hole(0.05, 0.01, 0.02, 0.01, 48);
  Mesh b = box(Eigen::Vector3d(0.06, -0.01, 0.0), Eigen::Vector3d(0.08, 0.01, 0.03), 1, "lug");
  Mesh c = cylinder(0.008, 0.01, 0.05, 32, "shaft");
  const std::vector<MassProperties> parts{exact(a, 2700), exact(b, 7850), exact(c, 4430)};
  const MassProperties sum = assemble(parts);
  // Independent: the first and second moments of all three added before the centre is taken.
  Moments m = exact_moments(a, 2700);
  m += exact_moments(b, 7850);
  m += exact_moments(c, 4430);
  expect_same(sum, to_mass_properties(m), 1e-12);
  EXPECT_NEAR(sum.mass, parts[0].mass + parts[1].mass + parts[2].mass, 1e-15);
}

TEST(RigidBodyInertia, PrincipalAxes) {
  const Mesh part = test::disk_with_offset_hole(0.05, 0.01, 0.02, 0.01, 48);
  Mesh turned = part;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  turned.transform(pose);
  const MassProperties p = exact(turned, 2700), flat = exact(part, 2700);
  const PrincipalAxes pa = principal_axes(p.inertia);
  // The moments are the unturned body's diagonal (x, y, z are its principal axes by symmetry).
  Eigen::Vector3d d = flat.inertia.diagonal();
  std::sort(d.data(), d.data() + 3);
  EXPECT_LE((pa.moments - d).norm(), 1e-12 * d.norm());
  EXPECT_NEAR(pa.axes.determinant(), 1.0, 1e-12);
  EXPECT_LE((pa.axes * pa.moments.asDiagonal() * pa.axes.transpose() - p.inertia).norm(), 1e-12 * p.inertia.norm());
  // The largest moment is about the disk's axis, turned.
  EXPECT_NEAR(std::abs(pa.axes.col(2).dot(pose.linear() * Eigen::Vector3d::UnitZ())), 1.0, 1e-9);
}

}  // namespace
}  // namespace poise::geometry
