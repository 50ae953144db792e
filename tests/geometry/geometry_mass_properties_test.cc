// Mass properties: the divergence-theorem formula against closed-form solids, the Embree
// ray-cast integration against both, its convergence with ray density, determinism.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <numbers>

#include "geometry/embree_scene.h"
#include "geometry/generators.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_io.h"
#include "test_util.h"

namespace poise::geometry {
namespace {

constexpr double kPi = std::numbers::pi;

double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }
double rel_matrix(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) { return (a - b).norm() / b.norm(); }

Eigen::Isometry3d some_pose() {
  Eigen::Isometry3d f = Eigen::Isometry3d::Identity();
  f.linear() = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX())).toRotationMatrix();
  f.translation() = Eigen::Vector3d(0.013, -0.021, 0.007);
  return f;
}

TEST(MassProperties, BoxExactAndRotated) {
  const Eigen::Vector3d size(0.04, 0.02, 0.01);
  Mesh b = box(-size / 2, size / 2, 3, "box");
  EXPECT_EQ(check_closed(b), "");
  const double rho = 7850, m = rho * size.prod();
  const MassProperties ref = solid_box(m, size);
  const MassProperties p = to_mass_properties(exact_moments(b, rho));
  EXPECT_LT(rel(p.mass, m), 1e-12);
  EXPECT_LT(rel_matrix(p.inertia, ref.inertia), 1e-12);
  // Rotated and moved: the inertia turns as R I R^T, the centre moves with the pose.
  const Eigen::Isometry3d f = some_pose();
  b.transform(f);
  const MassProperties q = to_mass_properties(exact_moments(b, rho));
  EXPECT_LT((q.com - f.translation()).norm(), 1e-14);
  const Eigen::Matrix3d turned = f.linear() * ref.inertia * f.linear().transpose();
  EXPECT_LT(rel_matrix(q.inertia, turned), 1e-12);
  // Ray cast: a tilted box is cut by the ray grid everywhere; 0.1% at 200 rays per side.
  const EmbreeScene scene({b}, true);
  RayCastStats st;
  const MassProperties r = to_mass_properties(raycast_moments(scene, {rho}, {2, 200}, &st));
  EXPECT_EQ(st.open_rays, 0u);
  EXPECT_LT(rel(r.mass, m), 1e-3);
  EXPECT_LT((r.com - f.translation()).norm(), 1e-3 * size.norm());
  EXPECT_LT(rel_matrix(r.inertia, turned), 2e-3);
}

TEST(MassProperties, CylinderAgainstClosedForm) {
  const double r = 0.03, len = 0.05, rho = 2700;
  const double m = rho * kPi * r * r * len;
  const Mesh c = cylinder(r, -len / 2, len / 2, 256, "cyl");
  EXPECT_EQ(check_closed(c), "");
  const MassProperties ref = solid_cylinder_z(m, r, len);
  // Equal-area polygon: the mass is exact, the inertia within O(n^-4).
  const MassProperties p = to_mass_properties(exact_moments(c, rho));
  EXPECT_LT(rel(p.mass, m), 1e-12);
  EXPECT_LT(rel_matrix(p.inertia, ref.inertia), 1e-6);
  // Rays along the axis: the silhouette is a circle; along x it is a rectangle.
  for (int axis : {0, 2}) {
    const EmbreeScene scene({c}, true);
    const MassProperties q = to_mass_properties(raycast_moments(scene, {rho}, {axis, 300}));
    EXPECT_LT(rel(q.mass, m), 1e-3) << "axis " << axis;
    EXPECT_LT(q.com.norm(), 1e-6) << "axis " << axis;  // symmetric grid on a symmetric body
    EXPECT_LT(rel_matrix(q.inertia, ref.inertia), 2e-3) << "axis " << axis;
  }
}

// The simulator disk of Yang 2015: 16 through holes and two clump weights, in closed form.
TEST(MassProperties, DiskWithHolesAndClumps) {
  DiskSpec s;
  s.radius = 0.065;
  s.thickness = 0.012;
  s.density = 2700;
  const double d = 0.008, rh = d / 2;
  s.holes = yang2015_hole_pattern(d, kPi / 8);
  s.clumps = {{0, 0.01553, 7850, 0.016}, {11, 0.02581, 7850, 0.016}};  // on C_A at 0 deg, on C_B at 3 x 45 + 22.5 deg
  const Assembly parts = simulator_disk(s);
  ASSERT_EQ(parts.size(), 1u + 16u + 2u);
  for (const auto& b : parts) EXPECT_EQ(check_closed(b.mesh), "") << b.mesh.name;
  // Closed form: disk - 16 holes + clumps (cylinders of r_c, length m / (rho pi r_c^2), on z = t).
  const double t = s.thickness, mh = s.density * kPi * rh * rh * t, md = s.density * kPi * s.radius * s.radius * t;
  double mass = md - 16 * mh;
  Eigen::Vector3d first = Eigen::Vector3d(0, 0, t / 2) * mass;
  double jz = md * s.radius * s.radius / 2;  // about the disk axis
  for (const auto& h : s.holes) jz -= mh * (rh * rh / 2 + h.radius * h.radius);
  for (const auto& c : s.clumps) {
    const auto& h = s.holes[c.hole];
    const double rc = c.diameter / 2, len = c.mass / (c.density * kPi * rc * rc);
    mass += c.mass;
    first += c.mass * Eigen::Vector3d(h.radius * std::cos(h.angle), h.radius * std::sin(h.angle), t + len / 2);
    jz += c.mass * (rc * rc / 2 + h.radius * h.radius);
  }
  const Eigen::Vector3d com = first / mass;
  const double jz_com = jz - mass * (com.x() * com.x() + com.y() * com.y());
  const double e = std::hypot(com.x(), com.y());

  const MassProperties p = to_mass_properties(exact_moments(parts));
  EXPECT_LT(rel(p.mass, mass), 1e-12);
  EXPECT_LT((p.com - com).norm(), 1e-12);
  EXPECT_LT(rel(p.inertia(2, 2), jz_com), 1e-6);
  // Ray cast, one grid per part.
  RayCastStats st;
  const MassProperties q = to_mass_properties(raycast_moments(parts, {2, 200}, &st));
  EXPECT_EQ(st.open_rays, 0u);
  EXPECT_LT(rel(q.mass, mass), 1e-3);
  EXPECT_LT(std::abs(std::hypot(q.com.x(), q.com.y()) - e), 1e-3 * e);
  EXPECT_LT(rel(q.inertia(2, 2), jz_com), 1e-3);
  // The whole disk in one scene and one grid (holes as inverted shells, winding 0 inside).
  std::vector<Mesh> meshes;
  std::vector<double> rho;
  for (const auto& b : parts) meshes.push_back(b.mesh), rho.push_back(b.density);
  const EmbreeScene one(meshes, true);
  const MassProperties u = to_mass_properties(raycast_moments(one, rho, {2, 400}));
  EXPECT_LT(rel(u.mass, mass), 1e-3);
  EXPECT_LT(rel(u.inertia(2, 2), jz_com), 1e-3);
}

TEST(MassProperties, RayCastConvergesToTheDivergenceFormula) {
  // An irregular closed mesh (a tetrahedron tilted against the grid), O(h^1.5..2).
  Mesh tet = load_mesh(test::source_path("tests/data/meshes/tetra.obj"), 0.01);
  tet.transform(some_pose());
  const Moments exact = exact_moments(tet, 1000);
  const EmbreeScene scene({tet}, true);
  double previous = 1.0;
  for (int n : {25, 100, 400}) {
    const Moments r = raycast_moments(scene, {1000}, {1, n});
    const double err = rel(r.mass, exact.mass);
    EXPECT_LT(err, previous / 3.0) << n << " rays per side";
    previous = err;
  }
  EXPECT_LT(previous, 2e-4);
}

TEST(MassProperties, SameResultForAnyThreadCount) {
  DiskSpec s;
  s.radius = 0.065;
  s.thickness = 0.012;
  s.density = 2700;
  s.holes = yang2015_hole_pattern(0.008, kPi / 8);
  s.wedge = 2e-5;
  s.wedge_angle = 1.0;
  const Assembly parts = simulator_disk(s);
  auto run = [&](int threads) {
    tbb::task_arena arena(threads);
    Moments m;
    arena.execute([&] { m = raycast_moments(parts, {2, 120}); });
    return m;
  };
  const Moments a = run(1), b = run(2);
  EXPECT_EQ(a.mass, b.mass);
  EXPECT_EQ(a.first, b.first);
  EXPECT_EQ(a.second, b.second);
}

// Face wedge: the top face tilted by w across the diameter shifts the centre of mass
// radially by w R / (8 t) (first order), towards the thick side.
TEST(MassProperties, WedgeShiftsTheCentreOfMass) {
  DiskSpec s;
  s.radius = 0.065;
  s.thickness = 0.012;
  s.density = 2700;
  s.wedge = 0.05e-3;
  s.wedge_angle = 0.0;
  s.segments = 512;
  const MassProperties p = to_mass_properties(exact_moments(simulator_disk(s)));
  // int x (slope x) dA / (pi R^2 t) with slope = w / (2R): (w / 2R) (pi R^4 / 4) / (pi R^2 t) = w R / (8 t)
  EXPECT_NEAR(p.com.x(), s.wedge * s.radius / (8 * s.thickness), 1e-4 * s.wedge * s.radius / (8 * s.thickness));
  EXPECT_NEAR(p.com.y(), 0.0, 1e-12);
}

// Two slabs overlapping by a layer of thickness e across the rays: every ray counts e twice,
// so the overlap's volume is e times the slabs' face, and its box is that layer.
TEST(MassProperties, OverlapVolumeAndPlaceFromTheRays) {
  const double e = 1e-6;  // 1 um into a 20 x 20 x 5 mm slab
  Mesh m = box({0, 0, 0}, {0.02, 0.02, 0.005}, 1, "slabs");
  m.append(box({0, 0, 0.005 - e}, {0.02, 0.02, 0.010}, 1, ""));
  RayGridOptions grid;
  grid.rays_per_side = 64;
  grid.axis = 2;
  RayCastStats stats;
  raycast_moments({{m, 1.0}}, grid, &stats);
  EXPECT_EQ(stats.overlap_rays, stats.rays);
  EXPECT_NEAR(stats.overlap_volume_m3, e * 0.02 * 0.02, 1e-9 * e * 0.02 * 0.02);
  EXPECT_NEAR(stats.overlap_box.min().z(), 0.005 - e, 1e-12);
  EXPECT_NEAR(stats.overlap_box.max().z(), 0.005, 1e-12);
  EXPECT_NEAR(stats.overlap_box.min().x(), 0.0, 1e-12);
  EXPECT_NEAR(stats.overlap_box.max().y(), 0.02, 1e-12);
  // Apart, nothing overlaps.
  Mesh apart = box({0, 0, 0}, {0.02, 0.02, 0.005}, 1, "apart");
  apart.append(box({0, 0, 0.006}, {0.02, 0.02, 0.010}, 1, ""));
  RayCastStats none;
  raycast_moments({{apart, 1.0}}, grid, &none);
  EXPECT_EQ(none.overlap_rays, 0u);
  EXPECT_EQ(none.overlap_volume_m3, 0.0);
  EXPECT_TRUE(none.overlap_box.isEmpty());
}

}  // namespace
}  // namespace poise::geometry
