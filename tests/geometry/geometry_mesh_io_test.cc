// Mesh loaders: good files give the right solid; each malformed file of the corpus
// (tests/data/meshes/bad_*) is refused with the line or triangle and what is wrong.
#include <gtest/gtest.h>

#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "geometry/generators.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_io.h"
#include "test_util.h"

namespace poise::geometry {
namespace {

std::string corpus(const std::string& name) { return test::source_path("tests/data/meshes/" + name); }

std::string load_error(const std::string& path) {
  try {
    load_mesh(path);
  } catch (const MeshFormatError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(MeshIo, ObjTetrahedronWithSlashesAndNegativeIndices) {
  const Mesh m = load_mesh(corpus("tetra.obj"), 1e-3);  // file in mm
  EXPECT_EQ(m.vertices.size(), 4u);
  EXPECT_EQ(m.triangles.size(), 4u);
  EXPECT_EQ(check_closed(m), "");
  EXPECT_NEAR(exact_moments(m, 1.0).mass, 8e-9 / 6.0, 1e-22);  // legs 2 mm
}

TEST(MeshIo, ObjQuadsAreFanned) {
  const Mesh m = load_mesh(corpus("cube_quads.obj"));
  EXPECT_EQ(m.triangles.size(), 12u);
  EXPECT_EQ(check_closed(m), "");
  const MassProperties p = to_mass_properties(exact_moments(m, 1000.0));
  EXPECT_NEAR(p.mass, 1000.0, 1e-9);
  EXPECT_NEAR(p.com.x(), 0.5, 1e-12);
  EXPECT_NEAR(p.inertia(0, 0), 1000.0 * 2.0 / 12.0, 1e-9);
}

TEST(MeshIo, AsciiStlIsWeldedAndClosed) {
  const Mesh m = load_mesh(corpus("tetra_ascii.stl"));
  EXPECT_EQ(m.vertices.size(), 4u);  // 12 STL vertices merged
  EXPECT_EQ(check_closed(m), "");
  EXPECT_NEAR(exact_moments(m, 1.0).mass, 8.0 / 6.0, 1e-12);
}

// What some exporters write: a UTF-8 byte-order mark, keywords in capitals, numbers with a
// '+'. The same tetrahedron, read as ASCII (not taken for a binary header).
TEST(MeshIo, AsciiStlWithByteOrderMarkCapitalsAndPlusSigns) {
  test::TempDir dir;
  std::ifstream in(corpus("tetra_ascii.stl"));
  std::stringstream text;
  text << in.rdbuf();
  std::string upper = text.str();
  for (const char* kw : {"solid", "facet", "normal", "outer", "loop", "vertex", "endloop", "endfacet", "endsolid"}) {
    const std::string k(kw);
    std::string K = k;
    for (auto& c : K) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    for (std::size_t at = upper.find(k); at != std::string::npos; at = upper.find(k, at + K.size())) upper.replace(at, k.size(), K);
  }
  std::string plus;
  for (std::size_t i = 0; i < upper.size(); ++i) {  // a '+' before every unsigned number
    const bool starts = std::isdigit(static_cast<unsigned char>(upper[i])) && i > 0 && upper[i - 1] == ' ';
    if (starts) plus += '+';
    plus += upper[i];
  }
  const std::string path = dir.file("bom.stl");
  std::ofstream(path, std::ios::binary) << "\xEF\xBB\xBF" << plus;
  const Mesh m = load_mesh(path);
  EXPECT_EQ(m.vertices.size(), 4u);
  EXPECT_EQ(check_closed(m), "");
  EXPECT_NEAR(exact_moments(m, 1.0).mass, 8.0 / 6.0, 1e-12);
  // An OBJ with a byte-order mark before its first vertex.
  std::ifstream obj(corpus("tetra.obj"));
  std::stringstream obj_text;
  obj_text << obj.rdbuf();
  std::ofstream(dir.file("bom.obj"), std::ios::binary) << "\xEF\xBB\xBF" << obj_text.str();
  EXPECT_EQ(load_mesh(dir.file("bom.obj"), 1e-3).triangles.size(), 4u);
}

TEST(MeshIo, BinaryStlRoundTrip) {
  test::TempDir dir;
  DiskSpec s;
  s.radius = 0.065;
  s.thickness = 0.01;
  s.density = 2700;
  s.holes = yang2015_hole_pattern(0.006, 0.3926990817);
  const Mesh disk = merge(simulator_disk(s), "disk");
  const std::string stl = (dir.path() / "disk.stl").string(), obj = (dir.path() / "disk.obj").string();
  write_stl(disk, stl, 1e-3);
  write_obj(disk, obj, 1e-3);
  const Mesh a = load_mesh(stl, 1e-3), b = load_mesh(obj, 1e-3);
  EXPECT_EQ(a.triangles.size(), disk.triangles.size());
  EXPECT_EQ(b.triangles.size(), disk.triangles.size());
  const double m0 = exact_moments(disk, 2700).mass;
  EXPECT_NEAR(exact_moments(a, 2700).mass, m0, 1e-6 * m0);  // float coordinates
  EXPECT_NEAR(exact_moments(b, 2700).mass, m0, 1e-8 * m0);
}

TEST(MeshIo, MalformedObjCorpus) {
  EXPECT_EQ(load_error(corpus("bad_obj_index.obj")),
            corpus("bad_obj_index.obj") + ":4: face vertex index 4 is out of range (3 vertices defined so far)");
  EXPECT_EQ(load_error(corpus("bad_obj_short_vertex.obj")),
            corpus("bad_obj_short_vertex.obj") + ":2: vertex needs 3 coordinates (x y z [w] or x y z r g b), got 2");
  EXPECT_EQ(load_error(corpus("bad_obj_number.obj")),
            corpus("bad_obj_number.obj") + ":3: vertex coordinate '1.5.2' is not a finite number");
  EXPECT_EQ(load_error(corpus("bad_obj_statement.obj")),
            corpus("bad_obj_statement.obj") +
                ":4: unknown OBJ statement 'curv' (expected v, f, vt, vn, o, g, s, usemtl, mtllib, l, p)");
  EXPECT_EQ(load_error(corpus("bad_obj_face_size.obj")),
            corpus("bad_obj_face_size.obj") + ":4: face needs at least 3 vertices, got 2");
  EXPECT_EQ(load_error(corpus("bad_obj_no_faces.obj")), corpus("bad_obj_no_faces.obj") + ": no faces ('f' lines)");
  EXPECT_EQ(load_error(corpus("bad_obj_face_token.obj")),
            corpus("bad_obj_face_token.obj") +
                ":4: face vertex 'x' is not a vertex index (1-based, or negative relative)");
}

TEST(MeshIo, MalformedAsciiStlCorpus) {
  EXPECT_EQ(load_error(corpus("bad_stl_four_vertices.stl")),
            corpus("bad_stl_four_vertices.stl") + ":14: facet has more than 3 vertices; STL facets are triangles");
  EXPECT_EQ(load_error(corpus("bad_stl_truncated.stl")),
            corpus("bad_stl_truncated.stl") + ":12: file ends inside a facet");
  EXPECT_EQ(load_error(corpus("bad_stl_vertex.stl")),
            corpus("bad_stl_vertex.stl") + ":5: vertex needs 3 coordinates, got 2");
  EXPECT_EQ(load_error(corpus("bad_stl_keyword.stl")),
            corpus("bad_stl_keyword.stl") + ":3: expected 'outer loop', got '    inner loop'");
}

std::string binary_stl(std::uint32_t declared, std::size_t records) {
  std::string b(80, ' ');
  b.append(reinterpret_cast<const char*>(&declared), 4);
  b.append(50 * records, '\0');
  return b;
}

TEST(MeshIo, MalformedBinaryStl) {
  auto err = [](const std::string& bytes) {
    try {
      read_stl(bytes, "part.stl");
    } catch (const MeshFormatError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(err(std::string(40, '\0')),
            "part.stl: 40 bytes: too short for a binary STL header (84 bytes) and not ASCII STL ('solid ...')");
  EXPECT_EQ(err(binary_stl(3, 2)),
            "part.stl: binary STL header declares 3 triangles (234 bytes) but the file has 184 bytes (truncated in triangle 2)");
  EXPECT_EQ(err(binary_stl(0, 0)), "part.stl: binary STL with no triangles");
  std::string nan_file = binary_stl(2, 2);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(nan_file.data() + 84 + 50 + 12 + 12 + 4, &nan, 4);  // triangle 1, vertex 1, y
  EXPECT_EQ(err(nan_file), "part.stl: triangle 1, vertex 1: coordinate is not a finite number");
}

TEST(MeshIo, CheckClosedNamesTheTriangle) {
  Mesh m = load_mesh(corpus("cube_quads.obj"));
  m.triangles.pop_back();
  EXPECT_NE(check_closed(m).find("has no opposite edge (the mesh is open)"), std::string::npos);
  Mesh f = load_mesh(corpus("cube_quads.obj"));
  std::swap(f.triangles[0][1], f.triangles[0][2]);
  EXPECT_EQ(check_closed(f).substr(0, 11), "triangle 0:");
}

}  // namespace
}  // namespace poise::geometry
