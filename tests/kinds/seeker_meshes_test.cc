// The seeker's yaw ring, pitch barrel and housing from a designer's meshes ([geometry] ring_mesh,
// barrel_mesh, housing_mesh, mesh_unit; issue 17): meshes exported by the generator give the
// generated frames' beam and clearance (to the float32 rounding of STL), a moved mesh moves the
// clearance by its offset, and each refusal names the file, line and key (exit 2).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "geometry/generators.h"
#include "geometry/mesh_io.h"
#include "geometry/obstruction.h"
#include "kinds/seeker_los/seeker_clearance.h"
#include "model_files/seeker_geometry.h"
#include "model_files/seeker_model.h"
#include "engine/study_files/toml_reader.h"
#include "test_util.h"

using namespace poise::kinds::seeker_los;  // the kinds' and model files' own namespaces
using namespace poise::model_files;  // the kinds' and model files' own namespaces

namespace poise::engine {
namespace {

using test::TempDir;
constexpr double kDeg = 3.14159265358979323846 / 180.0;

// The shipped model (meshes made by the build into examples/user_parts/meshes/seeker/) and the
// model whose frames are generated from the same [geometry].
TEST(SeekerMeshes, ExportedFramesGiveTheGeneratedBeamAndClearance) {
  const SeekerModel by_mesh = load_seeker_model(test::source_path("models/seeker_frames_from_meshes.toml"));
  const SeekerModel generated = load_seeker_model(test::source_path("models/seeker_two_axis_wang2011.toml"));
  ASSERT_TRUE(by_mesh.meshes.ring && by_mesh.meshes.barrel && by_mesh.meshes.housing);
  EXPECT_FALSE(generated.meshes.ring);
  EXPECT_EQ(by_mesh.meshes.ring_file, test::source_path("examples/user_parts/meshes/seeker/ring.stl"));
  const geometry::SeekerScenes a(*by_mesh.geometry, seeker_scene_meshes(by_mesh), 1024);
  const geometry::SeekerScenes b(*generated.geometry, seeker_scene_meshes(generated), 1024);
  // STL stores float32: 60 mm is kept to 4 nm, so clearances agree to well under 0.1 um.
  for (const auto& [yaw, pitch] : {std::pair{0.0, 0.0}, {30.0, 0.0}, {0.0, 30.0}, {-30.0, 30.0}}) {
    const geometry::GimbalPose pose = geometry::nominal_pose(yaw * kDeg, pitch * kDeg);
    const auto ca = a.clearance(pose), cb = b.clearance(pose);
    EXPECT_NEAR(ca.ring_housing, cb.ring_housing, 1e-7) << yaw << " " << pitch;
    EXPECT_NEAR(ca.barrel_housing, cb.barrel_housing, 1e-7) << yaw << " " << pitch;
    EXPECT_NEAR(ca.barrel_ring, cb.barrel_ring, 1e-7) << yaw << " " << pitch;
    // A ray grazing an edge may fall either side of a 4 nm move: at most a few of 1024.
    EXPECT_NEAR(a.trace_beam(pose).fraction(), b.trace_beam(pose).fraction(), 3.0 / 1024) << yaw << " " << pitch;
  }
  EXPECT_NEAR(nominal_min_clearance(by_mesh, 3, 3), nominal_min_clearance(generated, 3, 3), 1e-7);
  EXPECT_GT(nominal_min_clearance(by_mesh, 3, 3), 1e-3);  // the case is not trivial: 1.41 mm
}

// A housing mesh of a different size is what the clearance sees: a housing bored 2 mm larger
// (radius 60 mm) adds 2 mm (to the polygon's apothem) to the ring's clearance
// at yaw 0, which is set by the ring's corner against the housing cylinder.
TEST(SeekerMeshes, TheHousingMeshSetsTheClearance) {
  TempDir d;
  geometry::SeekerGeometry wider;
  wider.housing_radius = 0.060;
  geometry::write_stl(geometry::seeker_meshes(wider).housing, d.file("housing.stl"), 1e-3);
  const std::string model = test::source_path("models/seeker_frames_from_meshes.toml");
  const SeekerModel m = load_seeker_model(model, {{"geometry.housing_mesh", d.file("housing.stl")}});
  ASSERT_TRUE(m.meshes.housing);
  const SeekerModel nominal = load_seeker_model(model);
  const auto pose = geometry::nominal_pose(0, 0);
  const double moved = geometry::SeekerScenes(*m.geometry, seeker_scene_meshes(m), 16).clearance(pose).ring_housing;
  const double base = geometry::SeekerScenes(*nominal.geometry, seeker_scene_meshes(nominal), 16).clearance(pose).ring_housing;
  EXPECT_NEAR(moved - base, 0.002 * std::cos(3.14159265358979323846 / 96), 1e-7);
}

TEST(SeekerMeshes, RefusalsNameTheFileLineAndKey) {
  TempDir d;
  const std::string text = test::read_text(test::source_path("models/seeker_frames_from_meshes.toml"));
  const std::string mesh_dir = test::source_path("examples/user_parts/meshes/seeker/");
  geometry::Mesh open = geometry::load_mesh(mesh_dir + "ring.stl", 1e-3);
  open.triangles.erase(open.triangles.begin() + 5);
  std::filesystem::create_directories(d.file("meshes"));
  geometry::write_stl(open, d.file("meshes/ring_open.stl"), 1e-3);
  auto refused = [&](const std::string& model_text, const std::string& expected) {
    test::write_text(d.file("seeker.toml"), model_text);
    test::write_text(d.file("study.toml"), test::replace_once(
        test::read_text(test::source_path("studies/los_obstruction_from_meshes.toml")),
        "../models/seeker_frames_from_meshes.toml", d.file("seeker.toml")));
    const test::RunResult r = test::run_poise(d, "validate '" + d.file("study.toml") + "'");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  };
  // Paths of the copy are relative to its folder.
  const std::string copy = test::replace_once(test::replace_once(test::replace_once(text,
      "../examples/user_parts/meshes/seeker/ring.stl", mesh_dir + "ring.stl"),
      "../examples/user_parts/meshes/seeker/barrel.stl", mesh_dir + "barrel.stl"),
      "../examples/user_parts/meshes/seeker/housing.stl", mesh_dir + "housing.stl");
  const std::string ring_key = "ring_mesh = \"" + mesh_dir + "ring.stl\"";
  const std::size_t line = static_cast<std::size_t>(
      std::count(copy.begin(), copy.begin() + static_cast<long>(copy.find(ring_key)), '\n') + 1);
  refused(test::replace_once(copy, ring_key, "ring_mesh = \"meshes/ring_open.stl\""),
          d.file("seeker.toml") + ":" + std::to_string(line) + ":13: key 'geometry.ring_mesh' = \"meshes/ring_open.stl\": "
          "expected \"\" (generated) or a closed, consistently oriented mesh file (STL or OBJ): " +
          d.file("meshes/ring_open.stl") + ": not closed");
  refused(test::replace_once(copy, "barrel_mesh = \"" + mesh_dir + "barrel.stl\"", "barrel_mesh = \"none.stl\""),
          "key 'geometry.barrel_mesh' = \"none.stl\": expected \"\" (generated) or a closed, consistently oriented mesh "
          "file (STL or OBJ): " + d.file("none.stl") + ": no such mesh file");
  refused(test::replace_once(copy, "mesh_unit = \"mm\"", "mesh_unit = \"ft\""), "key 'geometry.mesh_unit' = \"ft\"");
}

}  // namespace
}  // namespace poise::engine
