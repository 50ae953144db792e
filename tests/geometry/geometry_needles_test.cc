// Zero-area triangles ("needles") and OBJ polygons: needles the closed surface does not need
// are dropped on loading and the part keeps its figures; a needle that closes a T-junction
// is kept and accepted; polygons are cut by ear clipping, without slivers at collinear
// vertices and without triangles outside a concave face.
#include <gtest/gtest.h>

#include <sstream>

#include "geometry/generators.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_needles.h"
#include "geometry/polygon_triangulation.h"
#include "closed_form_meshes.h"
#include "test_util.h"

namespace poise::geometry {
namespace {

Mesh cube(const std::string& name) {
  return box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(0.01), 1, name);  // 10 mm
}

// Two collinear triangles back to back on a cube edge (a, its midpoint, b): what an OpenSCAD
// export left in a closed part. Their edges pair up among themselves.
Mesh cube_with_needle_pair() {
  Mesh m = cube("needles.stl");
  const Triangle& t = m.triangles[0];
  const std::uint32_t a = t[0], b = t[1];
  m.vertices.push_back((m.vertices[a] + m.vertices[b]) / 2.0);
  const auto c = static_cast<std::uint32_t>(m.vertices.size() - 1);
  m.triangles.push_back({a, b, c});
  m.triangles.push_back({a, c, b});
  return m;
}

// A cube whose triangle 0 is split at the middle of its edge (p, q) while the neighbour across
// that edge is not: the needle (p, q, m) closes the T-junction.
Mesh cube_with_t_junction() {
  Mesh m = cube("tjunction.stl");
  const Triangle t = m.triangles[0];
  const std::uint32_t p = t[0], q = t[1], r = t[2];
  m.vertices.push_back((m.vertices[p] + m.vertices[q]) / 2.0);
  const auto mid = static_cast<std::uint32_t>(m.vertices.size() - 1);
  m.triangles[0] = {p, mid, r};
  m.triangles.push_back({mid, q, r});
  m.triangles.push_back({p, q, mid});
  return m;
}

TEST(Needles, PairBackToBackIsDroppedOnLoading) {
  test::TempDir dir;
  const Mesh m = cube_with_needle_pair();
  EXPECT_TRUE(zero_area(m, m.triangles.size() - 1));
  EXPECT_EQ(unneeded_needles(m), (std::vector<std::size_t>{m.triangles.size() - 2, m.triangles.size() - 1}));
  // As exported the surface is closed with them (they add nothing): check_mesh() accepts it.
  EXPECT_EQ(check_mesh(m).zero_area_triangles.count, 2u);
  test::write_text(dir.file("needles.stl"), test::ascii_stl(m, 1e-3));
  LoadReport report;
  const Mesh loaded = load_mesh(dir.file("needles.stl"), 1e-3, &report);
  EXPECT_EQ(report.needles.dropped, 2u);
  EXPECT_NE(report.needles.first.find("triangle 12 (line "), std::string::npos) << report.needles.first;
  EXPECT_NE(report.needles.first.find(") mm"), std::string::npos) << report.needles.first;  // in the file's unit
  const MeshCheck c = check_mesh(loaded);
  ASSERT_TRUE(c.ok()) << c.errors.front();
  EXPECT_EQ(loaded.triangles.size(), 12u);
  const Moments exact = exact_moments(cube(""), 2700.0), got = exact_moments(loaded, 2700.0);
  EXPECT_NEAR(got.mass, exact.mass, 1e-12 * exact.mass);
}

TEST(Needles, ANeedleThatClosesATJunctionIsKeptAndAccepted) {
  const Mesh m = cube_with_t_junction();
  EXPECT_TRUE(unneeded_needles(m).empty());
  Mesh dropped = m;
  EXPECT_EQ(drop_needles(dropped).dropped, 0u);
  const MeshCheck c = check_mesh(m);
  ASSERT_TRUE(c.ok()) << c.errors.front();
  EXPECT_EQ(c.zero_area_triangles.count, 1u);
  EXPECT_EQ(c.zero_area_triangles.first_triangle, m.triangles.size() - 1);
  EXPECT_NEAR(c.volume_m3, 1e-6, 1e-18);
  // Without it the T-junction is open: the needle was needed, and is degenerate there.
  Mesh open = m;
  open.triangles.pop_back();
  const MeshCheck oc = check_mesh(open);
  EXPECT_EQ(oc.open_edges.count, 3u);
}

TEST(Needles, RepeatedVertexAndLooseNeedlesAreDropped) {
  Mesh m = cube("loose.obj");
  m.triangles.push_back({0, 0, 1});  // a repeated vertex: its two edges cancel
  const std::size_t n = m.triangles.size();
  Mesh kept = m;
  EXPECT_EQ(drop_needles(kept).dropped, 1u);
  EXPECT_EQ(kept.triangles.size(), n - 1);
  EXPECT_TRUE(check_mesh(kept).ok());
}

TEST(Polygons, CollinearVerticesMakeNoSlivers) {
  // A 10 x 10 x 10 cube whose bottom edge y = z = 0 has a vertex at its middle (9), shared
  // by the two faces along it, written as pentagons starting at a corner so that a fan from
  // the first vertex would cut a zero-area triangle (1, 9, 2).
  const std::string obj =
      "v 0 0 0\nv 10 0 0\nv 10 10 0\nv 0 10 0\nv 0 0 10\nv 10 0 10\nv 10 10 10\nv 0 10 10\nv 5 0 0\n"
      "f 1 4 3 2 9\n"   // bottom, z = 0, outward -z
      "f 1 9 2 6 5\n"   // front, y = 0, outward -y
      "f 5 6 7 8\nf 2 3 7 6\nf 3 4 8 7\nf 1 5 8 4\n";
  std::istringstream in(obj);
  const Mesh m = read_obj(in, "pentagons.obj", 1e-3);
  for (std::size_t k = 0; k < m.triangles.size(); ++k) EXPECT_FALSE(zero_area(m, k)) << describe_triangle(m, k);
  const MeshCheck c = check_mesh(m);
  ASSERT_TRUE(c.ok()) << c.errors.front();
  EXPECT_EQ(c.zero_area_triangles.count, 0u);
  EXPECT_NEAR(c.volume_m3, 1e-6, 1e-18);
  EXPECT_EQ(m.triangles.size(), 14u);  // 3 + 3 + 4 x 2
}

TEST(Polygons, ConcaveFaceIsCutInsideIt) {
  // An L-shaped face listed from a corner next to its reflex corner: a fan from there would
  // make a triangle turned the other way, outside the L.
  const std::vector<Eigen::Vector3d> v{{2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}, {0, 0, 0}, {2, 0, 0}};
  const std::vector<std::uint32_t> poly{0, 1, 2, 3, 4, 5};
  const std::vector<Triangle> tris = triangulate_polygon(v, poly);
  ASSERT_EQ(tris.size(), 4u);
  double area = 0.0;
  for (const Triangle& t : tris) {
    const double z = (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).z();
    EXPECT_GT(z, 0.0) << t[0] << " " << t[1] << " " << t[2];
    area += z / 2.0;
  }
  EXPECT_NEAR(area, 3.0, 1e-12);
  // The same L wound the other way: every triangle turned that way.
  const std::vector<std::uint32_t> back{5, 4, 3, 2, 1, 0};
  for (const Triangle& t : triangulate_polygon(v, back)) {
    EXPECT_LT((v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).z(), 0.0);
  }
  // All collinear: nothing can be cut; the fan is the answer, and nothing is lost.
  const std::vector<Eigen::Vector3d> line{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  EXPECT_EQ(triangulate_polygon(line, {0, 1, 2, 3}).size(), 2u);
}

}  // namespace
}  // namespace poise::geometry
