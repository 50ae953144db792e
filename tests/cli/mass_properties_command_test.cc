// `poise mass-properties`: figures of meshes with closed forms through every file format and
// unit, the assembly, the JSON keys, and the exit status and message of each refusal.
#include <gtest/gtest.h>

#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

#include "closed_form_meshes.h"
#include "geometry/generators.h"
#include "geometry/mesh_io.h"
#include "test_util.h"

namespace poise {
namespace {

using test::run_poise;
using test::TempDir;

constexpr double kR = 0.060, kRh = 0.011, kCx = 0.025, kT = 0.012, kRho = 2700;
constexpr int kN = 72;

geometry::Mesh disk() { return test::disk_with_offset_hole(kR, kRh, kCx, kT, kN); }

nlohmann::json run_json(const TempDir& dir, const std::string& args) {
  const auto r = run_poise(dir, "mass-properties " + args + " --json");
  EXPECT_EQ(r.status, 0) << r.err;
  return r.status == 0 ? nlohmann::json::parse(r.out) : nlohmann::json::object();
}

Eigen::Vector3d vec(const nlohmann::json& j) { return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()}; }
Eigen::Matrix3d mat(const nlohmann::json& j) {
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i) m.row(i) = vec(j[i]).transpose();
  return m;
}

void expect_figures(const nlohmann::json& j, const geometry::MassProperties& ref, double rel) {
  ASSERT_TRUE(j.contains("mass_kg"));
  EXPECT_NEAR(j["mass_kg"].get<double>(), ref.mass, rel * ref.mass);
  EXPECT_NEAR(j["volume_m3"].get<double>(), ref.mass / kRho, rel * ref.mass / kRho);
  EXPECT_LE((vec(j["centre_of_mass_m"]) - ref.com).norm(), rel * kR);
  EXPECT_LE((mat(j["inertia_kg_m2"]) - ref.inertia).norm(), rel * ref.inertia.norm());
}

TEST(MassPropertiesCommand, DiskWithHoleInEveryFormatAndUnit) {
  TempDir dir;
  const geometry::MassProperties ref = test::disk_with_offset_hole_closed_form(kR, kRh, kCx, kT, kN, kRho);
  const std::pair<const char*, double> units[] = {{"mm", 1e-3}, {"m", 1.0}, {"in", 0.0254}, {"cm", 1e-2}};
  for (const auto& [unit, size] : units) {
    const std::string u = unit;
    geometry::write_stl(disk(), dir.file("disk_" + u + ".stl"), size);
    geometry::write_obj(disk(), dir.file("disk_" + u + ".obj"), size);
    test::write_text(dir.file("disk_" + u + "_ascii.stl"), test::ascii_stl(disk(), size));
    const std::string density = u == "in" ? "\"2.7 g/cm^3\"" : "\"2700 kg/m^3\"";
    // Binary STL stores float32 (7 digits); OBJ 10 digits; ASCII STL 17 here.
    expect_figures(run_json(dir, dir.file("disk_" + u + ".stl") + " --unit " + u + " --density " + density), ref, 1e-6);
    expect_figures(run_json(dir, dir.file("disk_" + u + ".obj") + " --unit " + u + " --density " + density), ref, 1e-8);
    expect_figures(run_json(dir, dir.file("disk_" + u + "_ascii.stl") + " --unit " + u + " --density " + density), ref,
                   1e-12);
  }
  const auto j = run_json(dir, dir.file("disk_mm.obj") + " --unit mm --density \"2700 kg/m^3\"");
  std::vector<std::string> keys;
  for (const auto& [k, v] : j.items()) keys.push_back(k);
  EXPECT_EQ(keys, (std::vector<std::string>{"centre_of_mass_m", "inertia_kg_m2", "mass_kg", "principal_axes",
                                            "principal_moments_kg_m2", "raycast_check", "volume_m3"}));
  EXPECT_LT(j["raycast_check"]["mass_relative_difference"].get<double>(), 1e-3);
  EXPECT_LT(j["raycast_check"]["inertia_relative_difference"].get<double>(), 3e-3);
  // Principal moments: this disk's x, y, z are principal axes (mirror symmetric in y and z).
  Eigen::Vector3d d = ref.inertia.diagonal();
  std::sort(d.data(), d.data() + 3);
  EXPECT_LE((vec(j["principal_moments_kg_m2"]) - d).norm(), 1e-8 * d.norm());
}

TEST(MassPropertiesCommand, AssemblyOfPartsWithTheirDensities) {
  TempDir dir;
  geometry::write_obj(disk(), dir.file("disk.obj"), 1e-3);
  const geometry::Mesh shaft = geometry::cylinder(0.008, -0.03, 0.04, 40, "shaft");
  geometry::write_obj(shaft, dir.file("shaft.obj"), 1e-3);
  const auto j = run_json(dir, dir.file("disk.obj") + " " + dir.file("shaft.obj") +
                                   " --unit mm --density \"2700 kg/m^3\" --density \"7850 kg/m^3\"");
  ASSERT_EQ(j["parts"].size(), 2u);
  const geometry::MassProperties a = test::disk_with_offset_hole_closed_form(kR, kRh, kCx, kT, kN, kRho);
  const geometry::MassProperties b =
      test::ngon_prism_closed_form(geometry::equal_area_radius(0.008, 40), 40, -0.03, 0.04, 7850);
  // The sum, by hand: masses, first moments, parallel-axis terms.
  const double m = a.mass + b.mass;
  const Eigen::Vector3d c = (a.mass * a.com + b.mass * b.com) / m;
  auto shift = [&](const geometry::MassProperties& p) -> Eigen::Matrix3d {
    const Eigen::Vector3d d = p.com - c;
    return p.inertia + p.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  };
  geometry::MassProperties sum;
  sum.mass = m;
  sum.com = c;
  sum.inertia = shift(a) + shift(b);
  EXPECT_NEAR(j["mass_kg"].get<double>(), m, 1e-8 * m);
  EXPECT_LE((vec(j["centre_of_mass_m"]) - c).norm(), 1e-9);
  EXPECT_LE((mat(j["inertia_kg_m2"]) - sum.inertia).norm(), 1e-8 * sum.inertia.norm());
  EXPECT_NEAR(j["parts"][1]["mass_kg"].get<double>(), b.mass, 1e-8 * b.mass);
  EXPECT_EQ(j["parts"][1]["density_kg_m3"].get<double>(), 7850.0);
  EXPECT_EQ(j["parts"][0]["shells"].get<int>(), 1);
  // Human output names the units and shows the assembly.
  const auto r = run_poise(dir, "mass-properties " + dir.file("disk.obj") + " " + dir.file("shaft.obj") +
                                    " --unit mm --density \"2700 kg/m^3\"");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("assembly of 2 parts (parallel-axis sum):"), std::string::npos);
  EXPECT_NE(r.out.find(" kg\n"), std::string::npos);
  EXPECT_NE(r.out.find("kg m^2"), std::string::npos);
  EXPECT_NE(r.out.find(") mm\n"), std::string::npos);
}

TEST(MassPropertiesCommand, RefusalsExitTwoWithTheirMessage) {
  TempDir dir;
  geometry::write_stl(disk(), dir.file("disk.stl"), 1e-3);
  geometry::Mesh open = disk();
  open.triangles.erase(open.triangles.begin() + 100);
  geometry::write_stl(open, dir.file("open.stl"), 1e-3);
  // Two boxes exported into one another: each closed, their common cube counted twice.
  geometry::Mesh overlap = geometry::box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.02, 0.02, 0.02), 1, "a");
  overlap.append(geometry::box(Eigen::Vector3d(0.01, 0.01, 0.01), Eigen::Vector3d(0.03, 0.03, 0.03), 1, "b"));
  geometry::write_obj(overlap, dir.file("overlap.obj"), 1e-3);
  test::write_text(dir.file("bad.stl"), "solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0\n");
  const std::string d = dir.file("disk.stl");
  const std::pair<std::string, std::string> cases[] = {
      {d + " --density \"2700 kg/m^3\"",
       "poise mass-properties: --unit is required: the length unit the mesh was exported in (mm, cm, m or in); STL "
       "and OBJ files do not say\n"},
      {d + " --unit ft --density \"2700 kg/m^3\"",
       "poise mass-properties: --unit 'ft': expected mm, cm, m or in (the length unit the mesh was exported in)\n"},
      {d + " --unit mm", "poise mass-properties: --density is required, e.g. --density \"2700 kg/m^3\" (aluminium)\n"},
      {d + " --unit mm --density \"2700 kg\"", "poise mass-properties: --density \"2700 kg\": "},
      {d + " --unit mm --density=\"-2700 kg/m^3\"",
       "poise mass-properties: --density \"-2700 kg/m^3\": expected a positive density, e.g. \"2700 kg/m^3\"\n"},
      {d + " " + d + " " + d + " --unit mm --density \"1 g/cm^3\" --density \"2 g/cm^3\"",
       "poise mass-properties: --density given 2 times for 3 meshes: give one for all, or one per mesh in their "
       "order\n"},
      {"--unit mm --density \"2700 kg/m^3\"",
       "poise mass-properties: no mesh given: poise mass-properties MESH... --unit mm --density \"2700 kg/m^3\"\n"},
      {dir.file("none.stl") + " --unit mm --density \"2700 kg/m^3\"",
       "poise mass-properties: " + dir.file("none.stl") + ": no such mesh file (or not a regular file)\n"},
      {dir.file("open.stl") + " --unit mm --density \"2700 kg/m^3\"",
       "poise mass-properties: " + dir.file("open.stl") + ": not closed: 3 open edges, the first at triangle "},
      {dir.file("bad.stl") + " --unit mm --density \"2700 kg/m^3\"",
       "poise mass-properties: " + dir.file("bad.stl") + ":4: vertex needs 3 coordinates, got 2\n"},
      {dir.file("overlap.obj") + " --unit mm --density \"2700 kg/m^3\"",
       "poise mass-properties: " + dir.file("overlap.obj") + ": shells overlap: "},
      {d + " --unit mm --density \"2700 kg/m^3\" --rays 2",
       "poise mass-properties: --rays 2: expected a whole number from 8 to 4096 (rays across the part)\n"},
      {d + " --unit mm --density \"2700 kg/m^3\" --rays abc",
       "poise mass-properties: --rays abc: expected a whole number from 8 to 4096 (rays across the part)\n"},
      {d + " --unit mm --density \"2700 kg/m^3\" --bogus",
       "poise mass-properties: unknown argument '--bogus' (see poise mass-properties --help)\n"},
  };
  for (const auto& [args, message] : cases) {
    const auto r = run_poise(dir, "mass-properties " + args);
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_EQ(r.err.substr(0, message.size()), message) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("Nothing was computed."), std::string::npos) << args;
    EXPECT_EQ(r.out, "") << args;
  }
}

TEST(MassPropertiesCommand, WrongUnitIsAWarningOnly) {
  TempDir dir;
  geometry::write_stl(disk(), dir.file("disk.stl"), 1e-3);  // numbers in mm
  const auto r = run_poise(dir, "mass-properties " + dir.file("disk.stl") + " --unit m --density \"2700 kg/m^3\"");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.err.find("poise mass-properties: warning: " + dir.file("disk.stl") +
                       ": 120 m across (the largest side of its bounding box), large for a part: is --unit m right? "
                       "In mm it would be 120 mm across."),
            std::string::npos)
      << r.err;
}

// An export that lists every face twice (as a MeshLab OBJ did): the divergence theorem would
// give twice the volume. Refused, naming the copies; --drop-duplicates removes them and the
// figures are the single part's.
TEST(MassPropertiesCommand, FacesListedTwiceAreRefusedOrDropped) {
  TempDir dir;
  geometry::Mesh twice = disk();
  const std::size_t n = twice.triangles.size();
  for (std::size_t k = 0; k < n; ++k) twice.triangles.push_back(twice.triangles[k]);
  test::write_text(dir.file("twice.obj"), geometry::obj_text(twice, 1e-3));
  const std::string args = dir.file("twice.obj") + " --unit mm --density \"2700 kg/m^3\"";
  const auto refused = run_poise(dir, "mass-properties " + args);
  EXPECT_EQ(refused.status, 2) << refused.err;
  EXPECT_NE(refused.err.find(std::to_string(n) + " triangles repeat another with the same vertices and winding"),
            std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("--drop-duplicates"), std::string::npos) << refused.err;
  const auto kept = run_poise(dir, "mass-properties " + args + " --drop-duplicates --json");
  ASSERT_EQ(kept.status, 0) << kept.err;
  EXPECT_NE(kept.err.find("dropped " + std::to_string(n) + " duplicate triangles"), std::string::npos) << kept.err;
  expect_figures(nlohmann::json::parse(kept.out),
                 geometry::to_mass_properties(geometry::exact_moments(disk(), kRho)), 1e-9);
}

// An assembly whose parts were exported in different units: --unit once per mesh, in order.
TEST(MassPropertiesCommand, UnitPerMesh) {
  TempDir dir;
  geometry::write_stl(disk(), dir.file("disk_mm.stl"), 1e-3);
  geometry::write_obj(disk(), dir.file("disk_m.obj"), 1.0);
  const auto j = run_json(dir, dir.file("disk_mm.stl") + " " + dir.file("disk_m.obj") +
                                   " --unit mm --unit m --density \"2700 kg/m^3\"");
  ASSERT_TRUE(j.contains("parts"));
  const double one = geometry::to_mass_properties(geometry::exact_moments(disk(), kRho)).mass;
  EXPECT_NEAR(j["parts"][0]["mass_kg"].get<double>(), one, 1e-6 * one);
  EXPECT_NEAR(j["parts"][1]["mass_kg"].get<double>(), one, 1e-6 * one);
  EXPECT_EQ(j["parts"][0]["unit"], "mm");
  EXPECT_EQ(j["parts"][1]["unit"], "m");
  EXPECT_NEAR(j["mass_kg"].get<double>(), 2 * one, 2e-6 * one);
  const auto r = run_poise(dir, "mass-properties " + dir.file("disk_mm.stl") + " " + dir.file("disk_m.obj") + " " +
                                    dir.file("disk_m.obj") + " --unit mm --unit m --density \"2700 kg/m^3\"");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--unit given 2 times for 3 meshes"), std::string::npos) << r.err;
}

// Two exports CAD tools make of a closed part: an OBJ that gives each triangle its own three
// vertices (assimp), and an STL whose shared vertices differ in their last digits (cracks of
// a few float32 ulps). Both are welded by default, say so, and give the part's figures;
// --weld 0 shows the cracks were there.
TEST(MassPropertiesCommand, UnsharedAndCrackedVerticesAreWelded) {
  TempDir dir;
  const geometry::Mesh m = disk();
  std::ostringstream obj, stl;
  stl.precision(17);
  stl << "solid cracked\n";
  std::size_t v = 0;
  for (std::size_t k = 0; k < m.triangles.size(); ++k) {
    stl << " facet normal 0 0 0\n  outer loop\n";
    for (int e = 0; e < 3; ++e) {
      const Eigen::Vector3d p = m.vertices[m.triangles[k][e]] * 1e3;  // mm
      obj << "v " << std::setprecision(17) << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
      // Each facet's copy of a vertex a few parts in 1e8 off the others (float32 ulps).
      const double crack = 1.0 + 3e-8 * static_cast<double>(k % 5);
      stl << "   vertex " << p.x() * crack << ' ' << p.y() * crack << ' ' << p.z() * crack << '\n';
    }
    obj << "f " << v + 1 << ' ' << v + 2 << ' ' << v + 3 << '\n';
    v += 3;
    stl << "  endloop\n endfacet\n";
  }
  stl << "endsolid cracked\n";
  test::write_text(dir.file("unshared.obj"), obj.str());
  test::write_text(dir.file("cracked.stl"), stl.str());
  const auto exact = geometry::to_mass_properties(geometry::exact_moments(m, kRho));
  for (const char* file : {"unshared.obj", "cracked.stl"}) {
    const std::string args = dir.file(file) + " --unit mm --density \"2700 kg/m^3\"";
    const auto r = run_poise(dir, "mass-properties " + args + " --json");
    ASSERT_EQ(r.status, 0) << file << ": " << r.err;
    EXPECT_NE(r.err.find("vertices onto others within"), std::string::npos) << r.err;
    expect_figures(nlohmann::json::parse(r.out), exact, 1e-6);
    const auto open = run_poise(dir, "mass-properties " + args + " --weld 0");
    EXPECT_EQ(open.status, 2) << file;
    EXPECT_NE(open.err.find("open edges"), std::string::npos) << open.err;
  }
}

}  // namespace
}  // namespace poise
