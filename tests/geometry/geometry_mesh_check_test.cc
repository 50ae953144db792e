// Mesh checks: each defect is found and named with the file, what is wrong and where; closed
// parts with several shells and cavities pass; a size that suggests the wrong unit warns.
#include <gtest/gtest.h>

#include <sstream>

#include "closed_form_meshes.h"
#include "geometry/generators.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"

namespace poise::geometry {
namespace {

// A tetrahedron as OBJ text: 4 faces on lines 6-9, outward.
const char* kTetObj =
    "# tet\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
    "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

Mesh tet() {
  std::istringstream in(kTetObj);
  return read_obj(in, "tet.obj");
}

Mesh unit_box(const std::string& name, const Eigen::Vector3d& lo = Eigen::Vector3d::Zero(), double side = 1.0) {
  Mesh m = box(lo, lo + Eigen::Vector3d::Constant(side), 1, name);
  return m;
}

TEST(MeshCheck, ClosedTetrahedronPasses) {
  const MeshCheck c = check_mesh(tet());
  EXPECT_TRUE(c.ok()) << c.errors.front();
  ASSERT_EQ(c.shells.size(), 1u);
  EXPECT_NEAR(c.volume_m3, 1.0 / 6.0, 1e-15);
  EXPECT_FALSE(c.shells[0].cavity);
}

TEST(MeshCheck, OpenEdgesNamedWithTriangleAndLine) {
  Mesh m = tet();
  m.triangles.pop_back();
  m.triangle_lines.pop_back();
  const MeshCheck c = check_mesh(m);
  ASSERT_EQ(c.errors.size(), 1u);
  // Where (the triangle's centroid, in the file's unit) and how wide: the missing face's
  // height, from an open edge to the farther end of the next.
  const std::string where = " at (0.333333, 0.333333, 0) m; the widest gap is 1.22474 m across, near (";
  EXPECT_TRUE(c.errors[0].starts_with("tet.obj: not closed: 3 open edges, the first at triangle 0 (line 6)" + where))
      << c.errors[0];
  EXPECT_EQ(c.open_edges.count, 3u);
  // Binary STL has no lines: the triangle alone.
  m.triangle_lines.clear();
  const std::string binary = check_mesh(m).errors[0];
  EXPECT_TRUE(binary.starts_with("tet.obj: not closed: 3 open edges, the first at triangle 0" + where)) << binary;
  EXPECT_THROW(require_valid_mesh(m), MeshCheckError);
}

TEST(MeshCheck, FlippedTriangleIsTheMinority) {
  Mesh m = unit_box("box.stl");
  std::swap(m.triangles[5][1], m.triangles[5][2]);
  const MeshCheck c = check_mesh(m);
  ASSERT_EQ(c.errors.size(), 1u);
  EXPECT_TRUE(c.errors[0].starts_with(
      "box.stl: inconsistent orientation: 1 triangle is flipped against their neighbours (their normals point the "
      "other way), the first is triangle 5 at ("))
      << c.errors[0];
  // Flipping triangle 0 names triangle 0, not its neighbours.
  Mesh f = unit_box("box.stl");
  std::swap(f.triangles[0][1], f.triangles[0][2]);
  EXPECT_EQ(check_mesh(f).flipped_triangles.first_triangle, 0u);
}

TEST(MeshCheck, NonManifoldEdge) {
  Mesh m = tet();
  m.triangle_lines.clear();
  m.vertices.emplace_back(1, 1, 1);
  m.triangles.push_back({0, 1, 4});  // a fin on edge (0, 1), already shared by two faces
  const MeshCheck c = check_mesh(m);
  EXPECT_EQ(c.non_manifold_edges.count, 1u);
  ASSERT_GE(c.errors.size(), 2u);
  EXPECT_TRUE(c.errors[0].starts_with("tet.obj: not closed: 2 open edges, the first at triangle 4 at (")) << c.errors[0];
  EXPECT_EQ(c.errors[1],
            "tet.obj: not manifold: 1 edge shared by three or more triangles that do not pair up (as many running each "
            "way), the first at triangle 0 at (0.333333, 0.333333, 0) m");
}

TEST(MeshCheck, DegenerateTriangles) {
  Mesh m = tet();
  m.triangle_lines.clear();
  m.triangles.push_back({1, 1, 2});  // repeated vertex
  m.vertices.emplace_back(2, 0, 0);
  m.triangles.push_back({0, 1, 4});  // collinear: zero area
  const MeshCheck c = check_mesh(m);
  EXPECT_EQ(c.degenerate_triangles.count, 2u);
  ASSERT_FALSE(c.errors.empty());
  EXPECT_NE(std::find(c.errors.begin(), c.errors.end(),
                      "tet.obj: 2 degenerate triangles (a repeated vertex or zero area), the first is triangle 4 at "
                      "(0.666667, 0.333333, 0) m"),
            c.errors.end());
}

TEST(MeshCheck, InsideOutShellRefused) {
  Mesh m = unit_box("box.stl");
  m.flip();
  const MeshCheck c = check_mesh(m);
  ASSERT_EQ(c.errors.size(), 1u);
  EXPECT_TRUE(c.errors[0].starts_with("box.stl: shell 1 of 1 (12 triangles from triangle 0 at (")) << c.errors[0];
  EXPECT_NE(c.errors[0].find(") m) has negative volume (-1 m^3) and lies inside no other shell: it is inside out (its "
                             "normals point inwards)"),
            std::string::npos)
      << c.errors[0];
  // An inverted box beside (not inside) a good one: the second shell is named.
  Mesh two = unit_box("two.stl");
  Mesh away = unit_box("", Eigen::Vector3d(3, 0, 0));
  away.flip();
  two.append(away);
  const MeshCheck c2 = check_mesh(two);
  ASSERT_EQ(c2.errors.size(), 1u);
  EXPECT_NE(c2.errors[0].find("two.stl: shell 2 of 2 (12 triangles from triangle 12 at ("),
            std::string::npos);
}

TEST(MeshCheck, CavityAndSeveralShellsAreOnePart) {
  Mesh m = unit_box("hollow.stl", Eigen::Vector3d::Zero(), 2.0);
  Mesh cavity = unit_box("", Eigen::Vector3d(0.5, 0.5, 0.5), 1.0);
  cavity.flip();
  m.append(cavity);
  m.append(unit_box("", Eigen::Vector3d(5, 0, 0), 1.0));  // a separate solid in the same file
  const MeshCheck c = check_mesh(m);
  EXPECT_TRUE(c.ok()) << c.errors.front();
  ASSERT_EQ(c.shells.size(), 3u);
  EXPECT_FALSE(c.shells[0].cavity);
  EXPECT_TRUE(c.shells[1].cavity);
  EXPECT_NEAR(c.shells[1].volume_m3, -1.0, 1e-12);
  EXPECT_NEAR(c.volume_m3, 8.0 - 1.0 + 1.0, 1e-12);
  // The generated simulator disk: holes are inverted cylinders sharing the disk's faces.
  DiskSpec d;
  d.radius = 0.065;
  d.thickness = 0.012;
  d.density = 2700;
  d.holes = yang2015_hole_pattern(0.0066, 0.3927);
  const Mesh disk = merge(simulator_disk(d), "disk");
  const MeshCheck dc = check_mesh(disk);
  EXPECT_TRUE(dc.ok()) << dc.errors.front();
  EXPECT_EQ(dc.shells.size(), 17u);
}

TEST(MeshCheck, SolidsTouchingAlongAnEdgeOrAFaceAreAccepted) {
  // Welded in one STL: boxes meeting along the edge x = y = 1, and along the face x = 3.
  const std::string text = test::ascii_stl(unit_box("a"), 1.0) +
                           test::ascii_stl(unit_box("b", Eigen::Vector3d(1, 1, 0)), 1.0) +
                           test::ascii_stl(unit_box("c", Eigen::Vector3d(2, 0, 0)), 1.0) +
                           test::ascii_stl(unit_box("d", Eigen::Vector3d(3, 0, 0)), 1.0);
  const Mesh m = read_stl(text, "touching.stl");
  const MeshCheck c = check_mesh(m);
  EXPECT_TRUE(c.ok()) << c.errors.front();
  EXPECT_GE(c.shared_edges.count, 2u);  // the edge x = y = 1 and the face x = 3's edges
  EXPECT_NEAR(c.volume_m3, 4.0, 1e-12);
  // A fourth triangle on a shared edge unbalances it: not manifold.
  Mesh bad = m;
  bad.triangle_lines.clear();
  const Triangle& t = bad.triangles[c.shared_edges.first_triangle];
  bad.vertices.emplace_back(9, 9, 9);
  bad.triangles.push_back({t[0], t[1], static_cast<std::uint32_t>(bad.vertices.size() - 1)});
  EXPECT_EQ(check_mesh(bad).non_manifold_edges.count, 1u);
}

TEST(MeshCheck, GenusOneDiskIsOneShell) {
  const MeshCheck c = check_mesh(test::disk_with_offset_hole(0.06, 0.01, 0.02, 0.012, 64));
  EXPECT_TRUE(c.ok());
  EXPECT_EQ(c.shells.size(), 1u);
}

TEST(MeshCheck, WrongUnitWarns) {
  Mesh m = unit_box("disk.stl", Eigen::Vector3d::Zero(), 60.0);  // "60" read as metres
  EXPECT_EQ(unit_warning(m, "m", 1.0),
            "disk.stl: 60 m across (the largest side of its bounding box), large for a part: is --unit m right? In "
            "mm it would be 60 mm across.");
  Mesh s = unit_box("disk.stl", Eigen::Vector3d::Zero(), 0.06e-3);  // "0.06" read as mm
  EXPECT_EQ(unit_warning(s, "mm", 1e-3),
            "disk.stl: 0.06 mm across (the largest side of its bounding box), small for a part: is --unit mm right? "
            "In m it would be 0.06 m across.");
  EXPECT_EQ(unit_warning(unit_box("ok.stl", Eigen::Vector3d::Zero(), 0.06), "mm", 1e-3), "");
}

TEST(MeshLoaders, SeveralAsciiSolidsAndObjVertexColours) {
  const Mesh a = unit_box("a");
  Mesh b = unit_box("b", Eigen::Vector3d(3, 0, 0));
  const std::string two = test::ascii_stl(a, 1.0) + test::ascii_stl(b, 1.0);
  const Mesh m = read_stl(two, "two.stl");
  EXPECT_EQ(m.triangles.size(), 24u);
  const MeshCheck c = check_mesh(m);
  EXPECT_TRUE(c.ok());
  EXPECT_EQ(c.shells.size(), 2u);
  EXPECT_EQ(m.triangle_lines.at(12), 88u);  // solid 1: lines 1-86 (12 facets of 7 lines); solid 2 from 87
  std::istringstream in(
      "v 0 0 0 1 0 0\nv 1 0 0 1 0 0\nv 0 1 0 0 1 0\nv 0 0 1 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
      "l 1 2\n");
  EXPECT_NEAR(check_mesh(read_obj(in, "colours.obj")).volume_m3, 1.0 / 6.0, 1e-15);
}

}  // namespace
}  // namespace poise::geometry
