// `poise mass-properties` on faulty CAD exports (issue 30): needles an export left are dropped
// with a note, shells that overlap by a trace are accepted with their overlap's volume and
// place, more is refused with them, and every mesh's every defect is named in one run, with
// places in the file's unit and the size of each defect.
#include <gtest/gtest.h>

#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

#include "geometry/generators.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_io.h"
#include "closed_form_meshes.h"
#include "test_util.h"

namespace poise {
namespace {

using test::run_poise;
using test::TempDir;

const std::string kDensity = " --density \"2700 kg/m^3\"";

geometry::Mesh box_mm(const Eigen::Vector3d& lo_mm, const Eigen::Vector3d& hi_mm, const std::string& name = "box") {
  return geometry::box(lo_mm * 1e-3, hi_mm * 1e-3, 1, name);
}

// Two 20 x 20 mm slabs stacked along z, the upper one reaching `overlap_mm` into the lower:
// each closed, their common layer counted twice. The rays run along z (the thinnest side),
// so every ray crosses the layer.
geometry::Mesh stacked_slabs(double overlap_mm) {
  geometry::Mesh m = box_mm({0, 0, 0}, {20, 20, 5}, "slabs");
  m.append(box_mm({0, 0, 5 - overlap_mm}, {20, 20, 10}));
  return m;
}

double mass_of(const geometry::Mesh& m) { return geometry::exact_moments(m, 2700.0).mass; }

TEST(MassPropertiesFaults, NeedlesOfAnExportAreDroppedWithANote) {
  TempDir dir;
  // A closed part with two collinear triangles back to back on an edge (an OpenSCAD export).
  geometry::Mesh m = box_mm({0, 0, 0}, {10, 10, 10}, "needles");
  const std::uint32_t a = m.triangles[0][0], b = m.triangles[0][1];
  m.vertices.push_back((m.vertices[a] + m.vertices[b]) / 2.0);
  const auto c = static_cast<std::uint32_t>(m.vertices.size() - 1);
  m.triangles.push_back({a, b, c});
  m.triangles.push_back({a, c, b});
  test::write_text(dir.file("needles.stl"), test::ascii_stl(m, 1e-3));
  const auto r = run_poise(dir, "mass-properties " + dir.file("needles.stl") + " --unit mm" + kDensity + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("dropped 2 zero-area triangles the closed surface does not need"), std::string::npos) << r.err;
  const double expected = mass_of(box_mm({0, 0, 0}, {10, 10, 10}));
  EXPECT_NEAR(nlohmann::json::parse(r.out)["mass_kg"].get<double>(), expected, 1e-12 * expected);
}

TEST(MassPropertiesFaults, TouchingShellsOverlappingByATraceAreAccepted) {
  TempDir dir;
  // A 2.5 x 2.5 mm block standing 1e-4 mm into a 20 x 20 x 5 mm slab (more than the default
  // weld, 3e-5 mm here, so its corners stay apart): 6.25e-4 mm^3 counted twice, some 3e-7 of
  // the part. The block's sides lie on the rays' cell lines (20 mm / 256 rays), so exactly
  // 32 x 32 rays cross the layer.
  const double trace_mm = 1e-4;
  geometry::Mesh m = box_mm({0, 0, 0}, {20, 20, 5}, "touching");
  m.append(box_mm({5, 5, 5 - trace_mm}, {7.5, 7.5, 10}));
  geometry::write_obj(m, dir.file("trace.obj"), 1e-3);
  const std::string args = "mass-properties " + dir.file("trace.obj") + " --unit mm" + kDensity;
  const auto r = run_poise(dir, args + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("shells overlap by about 0.000625 mm^3 counted twice (3.08e-07 of the part's volume; "
                       "accepted up to 1e-06, --max-overlap), from (5, 5, 4.9999) to (7.5, 7.5, 5) mm"),
            std::string::npos)
      << r.err;
  // The figures are those of the mesh, the layer counted twice.
  const double expected = mass_of(m);
  EXPECT_NEAR(nlohmann::json::parse(r.out)["mass_kg"].get<double>(), expected, 1e-9 * expected);
  // Not accepted when no overlap is: --max-overlap 0.
  const auto none = run_poise(dir, args + " --max-overlap 0");
  EXPECT_EQ(none.status, 2) << none.err;
  EXPECT_NE(none.err.find("shells overlap: 1024 of 65536 check rays"), std::string::npos) << none.err;
}

TEST(MassPropertiesFaults, OverlapAboveItsShareIsRefusedWithItsVolumeAndPlace) {
  TempDir dir;
  geometry::write_obj(stacked_slabs(1e-3), dir.file("overlap.obj"), 1e-3);  // 0.4 mm^3, 1e-4 of the part
  const std::string args = "mass-properties " + dir.file("overlap.obj") + " --unit mm" + kDensity;
  const auto r = run_poise(dir, args);
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_NE(r.err.find(dir.file("overlap.obj") + ": shells overlap: 65536 of 65536 check rays pass through material "
                       "enclosed by two shells (solids exported into one another), about 0.4 mm^3 counted twice (0.0001 "
                       "of the part's volume; accepted up to 1e-06, --max-overlap), from (0, 0, 4.999) to (20, 20, 5) mm"),
            std::string::npos)
      << r.err;
  const auto accepted = run_poise(dir, args + " --max-overlap 1e-3");
  EXPECT_EQ(accepted.status, 0) << accepted.err;
  for (const char* bad : {"abc", "-1e-6", "1", "nan"}) {
    const auto b = run_poise(dir, args + " --max-overlap " + bad);
    EXPECT_EQ(b.status, 2) << bad;
    EXPECT_NE(b.err.find("--max-overlap " + std::string(bad) + ": expected a share of the part's volume from 0 to "
                         "below 1"),
              std::string::npos)
        << b.err;
  }
}

// Three bad meshes and a good one: one run names every defect of every mesh, the good one's
// notes too, and computes nothing.
TEST(MassPropertiesFaults, EveryMeshAndEveryDefectAtOnce) {
  TempDir dir;
  geometry::Mesh open = box_mm({0, 0, 0}, {10, 10, 10});
  open.triangles.pop_back();
  geometry::Mesh flipped = open;  // open and, besides, a triangle turned over
  std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
  geometry::write_stl(open, dir.file("open.stl"), 1e-3);
  geometry::write_stl(flipped, dir.file("flipped.stl"), 1e-3);
  geometry::write_obj(stacked_slabs(1e-3), dir.file("overlap.obj"), 1e-3);
  geometry::write_obj(box_mm({0, 0, 0}, {10, 10, 10}), dir.file("good.obj"), 1e-3);
  const auto r = run_poise(dir, "mass-properties " + dir.file("open.stl") + " " + dir.file("good.obj") + " " +
                                    dir.file("flipped.stl") + " " + dir.file("none.stl") + " " +
                                    dir.file("overlap.obj") + " --unit mm" + kDensity);
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "");
  const std::string head = "poise mass-properties: ";
  for (const std::string& line :
       {head + dir.file("open.stl") + ": not closed: 3 open edges, the first at triangle ",
        head + dir.file("flipped.stl") + ": not closed: 3 open edges",
        head + dir.file("flipped.stl") + ": inconsistent orientation: 1 triangle is flipped",
        head + dir.file("none.stl") + ": no such mesh file", head + dir.file("overlap.obj") + ": shells overlap: "}) {
    EXPECT_NE(r.err.find(line), std::string::npos) << line << "\n" << r.err;
  }
  EXPECT_EQ(r.err.find("good.obj"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Nothing was computed."), std::string::npos);
  // Where, in the file's unit, and how wide: a missing triangle of a 10 mm cube.
  EXPECT_NE(r.err.find(") mm; the widest gap is "), std::string::npos) << r.err;
}

// A crack: one facet's copy of a vertex 0.001 mm off the others, along the face's normal.
// With --weld 0 the message gives its width and the weld that would close it.
TEST(MassPropertiesFaults, CrackWidthAndTheWeldThatClosesIt) {
  TempDir dir;
  const geometry::Mesh m = box_mm({0, 0, 0}, {10, 10, 10});
  std::ostringstream stl;
  stl << std::setprecision(17) << "solid cracked\n";
  bool moved = false;
  for (std::size_t k = 0; k < m.triangles.size(); ++k) {
    const Eigen::Vector3d n = m.face_normal(k).normalized();
    stl << " facet normal 0 0 0\n  outer loop\n";
    for (int e = 0; e < 3; ++e) {
      Eigen::Vector3d p = m.vertices[m.triangles[k][e]] * 1e3;
      if (!moved && n.z() > 0.5 && e == 0) {
        p.z() += 1e-3;  // out of the top face, 0.001 mm
        moved = true;
      }
      stl << "   vertex " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    }
    stl << "  endloop\n endfacet\n";
  }
  stl << "endsolid cracked\n";
  ASSERT_TRUE(moved);
  test::write_text(dir.file("cracked.stl"), stl.str());
  const std::string args = "mass-properties " + dir.file("cracked.stl") + " --unit mm" + kDensity;
  const auto r = run_poise(dir, args + " --weld 0");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("; the widest gap is 0.001 mm across, near ("), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(") mm (a crack: --weld \"0.002 mm\" would join its sides)"), std::string::npos) << r.err;
  const auto welded = run_poise(dir, args + " --weld \"0.002 mm\"");
  EXPECT_EQ(welded.status, 0) << welded.err;
}

}  // namespace
}  // namespace poise
