// Beam obstruction and clearance of the two-axis seeker: point queries against exact
// distances, the beam's unobstructed fraction against the area of the clipped footprint.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "geometry/generators.h"
#include "geometry/obstruction.h"

namespace poise::geometry {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(Obstruction, ClosestPointOnTriangle) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  bool face = false;
  EXPECT_TRUE(closest_point_on_triangle({0.2, 0.3, 2.0}, a, b, c, &face).isApprox(Eigen::Vector3d(0.2, 0.3, 0)));
  EXPECT_TRUE(face);
  EXPECT_TRUE(closest_point_on_triangle({-1, -1, 0.5}, a, b, c, &face).isApprox(a));
  EXPECT_FALSE(face);
  EXPECT_TRUE(closest_point_on_triangle({0.5, -2, 0}, a, b, c, &face).isApprox(Eigen::Vector3d(0.5, 0, 0)));
  EXPECT_TRUE(closest_point_on_triangle({1, 1, 0}, a, b, c).isApprox(Eigen::Vector3d(0.5, 0.5, 0)));
}

TEST(Obstruction, SignedDistanceBetweenBoxes) {
  const Mesh a = box({0, 0, 0}, {0.01, 0.01, 0.01}, 2, "a");
  const EmbreeScene b({box({0, 0, 0}, {0.01, 0.01, 0.01}, 2, "b")}, true);
  Eigen::Isometry3d gap = Eigen::Isometry3d::Identity();
  gap.translation() = Eigen::Vector3d(0.015, 0.002, 0.0);
  EXPECT_NEAR(min_signed_distance(a, gap, b), 0.005, 1e-12);
  Eigen::Isometry3d overlap = Eigen::Isometry3d::Identity();
  overlap.translation() = Eigen::Vector3d(0.008, 0.0, 0.0);  // 2 mm into b: a's vertices at depth 2 mm
  EXPECT_NEAR(min_signed_distance(a, overlap, b), -0.002, 1e-12);
}

// The beam of a pure yaw alpha meets the front wall's plane x = front_x in an ellipse of
// semi-axes a / cos(alpha) (y) and a (z), centred at y = front_x tan(alpha); the rays that
// pass are those inside the window opening R_w.
double clipped_fraction(const SeekerGeometry& g, double alpha) {
  const double cy = g.front_x * std::tan(alpha), ay = g.aperture_radius / std::cos(alpha), az = g.aperture_radius;
  // The opening is the revolve's n-gon of circumradius R_w: inside if within every edge's apothem.
  const int n = g.segments, m = 1500;
  const double apothem = g.window_radius * std::cos(std::numbers::pi / n);
  std::size_t in = 0, total = 0;
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) {
      const double u = -1 + (2 * i + 1.0) / m, v = -1 + (2 * j + 1.0) / m;
      if (u * u + v * v > 1) continue;
      ++total;
      const double y = cy + ay * u, z = az * v;
      const double phi = std::atan2(z, y), step = 2 * std::numbers::pi / n;
      const double mid = (std::floor(phi / step) + 0.5) * step;
      if (y * std::cos(mid) + z * std::sin(mid) < apothem) ++in;
    }
  }
  return static_cast<double>(in) / static_cast<double>(total);
}

TEST(Obstruction, BeamFractionMatchesTheClippedFootprint) {
  const SeekerGeometry g;
  const SeekerScenes scenes(g, 4096);
  EXPECT_EQ(scenes.trace_beam(nominal_pose(0, 0)).fraction(), 1.0);
  for (double alpha_deg : {20.0, 30.0}) {
    const double ref = clipped_fraction(g, alpha_deg * kDeg);
    const double f = scenes.trace_beam(nominal_pose(alpha_deg * kDeg, 0)).fraction();
    EXPECT_NEAR(f, ref, 0.005) << "yaw " << alpha_deg << " deg";
  }
  EXPECT_LT(clipped_fraction(g, 30 * kDeg), 0.97);  // the case is not trivial
  // The field's corner is clipped more than either axis alone.
  EXPECT_LT(scenes.trace_beam(nominal_pose(30 * kDeg, 30 * kDeg)).fraction(),
            scenes.trace_beam(nominal_pose(30 * kDeg, 0)).fraction());
}

TEST(Obstruction, ClearanceOfTheNominalSeeker) {
  const SeekerGeometry g;
  const SeekerScenes scenes(g, 16);
  const double y_out = g.pitch_span / 2 + g.bearing_width / 2;
  const double z_out = g.yaw_span / 2 - g.bearing_width / 2 - g.ring_gap, z_in = z_out - g.ring_section;
  const double apothem = g.housing_radius * std::cos(std::numbers::pi / g.segments);
  // Yaw 0: the ring's corner (y_out, z_out) against the housing cylinder's faces.
  const SeekerScenes::Clearance c0 = scenes.clearance(nominal_pose(0, 0));
  EXPECT_NEAR(c0.ring_housing, apothem - std::hypot(y_out, z_out), 0.3e-3);
  EXPECT_GT(c0.ring_housing, 0.0);
  // Pitch 30 deg: the barrel's top passes under the ring's top member; the closest point
  // is the member's edge (x = depth/2, z = z_in) against the barrel surface.
  const double beta = 30 * kDeg, hx = g.ring_depth / 2;
  const double axis_dist = std::abs(-hx * std::sin(beta) + z_in * std::cos(beta));
  const SeekerScenes::Clearance c30 = scenes.clearance(nominal_pose(0, beta));
  EXPECT_NEAR(c30.barrel_ring, axis_dist - g.barrel_radius, 0.05e-3);
  EXPECT_NEAR(c30.min(), c30.barrel_ring, 1e-12);
  // A barrel too long for the ring at 30 deg pitch: negative clearance (interference).
  SeekerGeometry tight = g;
  tight.yaw_span = 0.070;
  const SeekerScenes::Clearance ct = SeekerScenes(tight, 16).clearance(nominal_pose(0, beta));
  EXPECT_LT(ct.barrel_ring, 0.0);
}

}  // namespace
}  // namespace poise::geometry
