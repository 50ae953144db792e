// A designer's parts in a model file ([[geometry.part]]): the worked example's meshes made by
// its generator, read, checked and placed; the as-built assembly of one sample's draws equals
// the exact mass properties of the meshes moved, turned and scaled by hand; refusals.
#include "engine/study_files/user_parts.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <numbers>

#include "geometry/mass_properties.h"
#include "geometry/mesh_io.h"
#include "geometry/rigid_body_inertia.h"
#include "test_util.h"

namespace poise::engine {
namespace {

using test::TempDir;

// The example's parts file in a folder holding the generated meshes under meshes/.
std::string example(const TempDir& dir) {
  const std::string cmd = std::string("'") + ::poise::test::built_program("poise_make_example_meshes") + "' '" + dir.file("meshes") + "' >/dev/null";
  EXPECT_EQ(std::system(cmd.c_str()), 0);
  const std::string path = dir.file("rotor_parts.toml");
  test::write_text(path, test::read_text(test::source_path("examples/user_parts/rotor_parts.toml")));
  return path;
}

geometry::MassProperties exact_of(const geometry::Mesh& m, double rho) {
  return geometry::to_mass_properties(geometry::exact_moments(m, rho));
}

TEST(UserParts, ExampleAsDrawnAndAsBuilt) {
  TempDir dir;
  const UserParts parts = load_user_parts_file(example(dir));
  ASSERT_EQ(parts.parts.size(), 4u);
  EXPECT_TRUE(parts.warnings.empty());
  EXPECT_EQ(parts.parts[1].mesh_file, dir.file("meshes/rotor/hub.obj"));
  const UserPartsSampler sampler(parts);
  // disk: density, position (3), angle (3), scale; hub: position (3); clump: position (3).
  ASSERT_EQ(sampler.dimension(), 1u + 3u + 3u + 1u + 3u + 3u);
  EXPECT_EQ(sampler.columns()[0].name, "rotor_disk_ddensity_kg_m3");
  EXPECT_EQ(sampler.columns()[7].name, "rotor_disk_scale_ppm");

  // Independent: load the four files, place the clump by hand, integrate the moved meshes.
  const std::string rotor = dir.file("meshes/rotor/");
  geometry::Mesh disk = geometry::load_mesh(rotor + "rotor_disk.stl", 1e-3);
  geometry::Mesh hub = geometry::load_mesh(rotor + "hub.obj", 1e-3);
  geometry::Mesh shaft = geometry::load_mesh(rotor + "shaft.stl", 1e-3);
  geometry::Mesh clump = geometry::load_mesh(rotor + "clump_weight.stl", 1e-3);
  Eigen::Isometry3d clump_pose = Eigen::Isometry3d::Identity();
  clump_pose.linear() = Eigen::AngleAxisd(std::numbers::pi / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  clump_pose.translation() = Eigen::Vector3d(0.051, 0.0, 0.012);
  geometry::Mesh placed_clump = clump;
  placed_clump.transform(clump_pose);
  geometry::Moments m = geometry::exact_moments(disk, 2700);
  m += geometry::exact_moments(hub, 7850);
  m += geometry::exact_moments(shaft, 7850);
  m += geometry::exact_moments(placed_clump, 7850);
  const geometry::MassProperties ref = geometry::to_mass_properties(m);

  std::vector<double> u(sampler.dimension(), 0.5), values(sampler.dimension());
  const geometry::MassProperties nominal = sampler.as_built(u, values);
  EXPECT_NEAR(nominal.mass, ref.mass, 1e-12 * ref.mass);
  EXPECT_LE((nominal.com - ref.com).norm(), 1e-15);
  EXPECT_LE((nominal.inertia - ref.inertia).norm(), 1e-12 * ref.inertia.norm());
  // The clump (12.6 g on the 51 mm circle) is the whole static unbalance about z.
  const double clump_mass = exact_of(clump, 7850).mass;
  EXPECT_NEAR(clump_mass, 7850 * std::numbers::pi * 0.008 * 0.008 * 0.008, 1e-6 * clump_mass);  // rounding of float32
  const Eigen::Vector3d u_nominal =
      geometry::static_unbalance(nominal, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(u_nominal.norm(), clump_mass * 0.051, 1e-9);
  EXPECT_NEAR(u_nominal.z(), 0.0, 1e-18);

  // A sample off the nominal: every draw away from its median.
  for (std::size_t k = 0; k < u.size(); ++k) u[k] = 0.1 + 0.8 * static_cast<double>((k * 7 + 3) % 10) / 9.0;
  const auto dev = sampler.draw(u, values);
  const geometry::MassProperties built = sampler.as_built(u, values);
  EXPECT_EQ(values[0], dev[0].density);  // kg/m^3 shown as drawn
  EXPECT_NEAR(values[1], dev[0].translation.x() / 1e-3, 1e-9);
  EXPECT_GT(std::abs(dev[0].scale), 0.0);
  // By hand: the disk scaled about its centre of mass, turned by its rotation vector and moved.
  const geometry::MassProperties disk0 = exact_of(disk, 1.0);
  const double s = 1.0 + dev[0].scale;
  for (auto& v : disk.vertices) v = disk0.com + s * (v - disk0.com);
  Eigen::Isometry3d disk_pose = Eigen::Isometry3d::Identity();
  disk_pose.linear() = Eigen::AngleAxisd(dev[0].rotation.norm(), dev[0].rotation.normalized()).toRotationMatrix();
  disk_pose.translation() = dev[0].translation;
  disk.transform(disk_pose);
  hub.transform(Eigen::Isometry3d(Eigen::Translation3d(dev[1].translation)));
  placed_clump.transform(Eigen::Isometry3d(Eigen::Translation3d(dev[3].translation)));
  geometry::Moments mb = geometry::exact_moments(disk, 2700 + dev[0].density);
  mb += geometry::exact_moments(hub, 7850);
  mb += geometry::exact_moments(shaft, 7850);
  mb += geometry::exact_moments(placed_clump, 7850);
  const geometry::MassProperties by_hand = geometry::to_mass_properties(mb);
  EXPECT_NEAR(built.mass, by_hand.mass, 1e-12 * by_hand.mass);
  EXPECT_LE((built.com - by_hand.com).norm(), 1e-14);
  EXPECT_LE((built.inertia - by_hand.inertia).norm(), 1e-11 * by_hand.inertia.norm());
  EXPECT_GT((built.com - nominal.com).norm(), 1e-7);  // the draws moved it
}

TEST(UserParts, RefusedAtTheirKey) {
  TempDir dir;
  const std::string path = example(dir);
  const std::string text = test::read_text(path);
  auto error_of = [&](const std::string& changed) {
    test::write_text(path, changed);
    try {
      load_user_parts_file(path);
    } catch (const ValidationError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  // An open mesh: the checker's message at the part's mesh key.
  geometry::Mesh open = geometry::load_mesh(dir.file("meshes/rotor/hub.obj"));
  open.triangles.pop_back();
  geometry::write_obj(open, dir.file("meshes/rotor/hub_open.obj"));
  std::string e = error_of(test::replace_once(text, "meshes/rotor/hub.obj", "meshes/rotor/hub_open.obj"));
  EXPECT_NE(e.find(path +
                   ":47:8: key 'geometry.part[1].mesh' = \"meshes/rotor/hub_open.obj\": expected a closed, "
                   "consistently oriented mesh file (STL or OBJ): " +
                   dir.file("meshes/rotor/hub_open.obj") + ": not closed: 3 open edges, the first at triangle "),
            std::string::npos)
      << e;
  // Two closed shells enclosing common material.
  geometry::Mesh twice = geometry::load_mesh(dir.file("meshes/rotor/hub.obj"));
  geometry::Mesh moved = twice;
  moved.transform(Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.0, 0.005)));
  twice.append(moved);
  geometry::write_obj(twice, dir.file("meshes/rotor/hub_twice.obj"));
  e = error_of(test::replace_once(text, "meshes/rotor/hub.obj", "meshes/rotor/hub_twice.obj"));
  EXPECT_NE(e.find("key 'geometry.part[1].mesh' = \"meshes/rotor/hub_twice.obj\": expected a closed, consistently "
                   "oriented mesh file (STL or OBJ): " +
                   dir.file("meshes/rotor/hub_twice.obj") + ": shells overlap: "),
            std::string::npos)
      << e;
  e = error_of(test::replace_once(text, "meshes/rotor/shaft.stl", "meshes/rotor/none.stl"));
  EXPECT_NE(e.find("key 'geometry.part[2].mesh' = \"meshes/rotor/none.stl\": expected a closed, consistently oriented "
                   "mesh file (STL or OBJ): " +
                   dir.file("meshes/rotor/none.stl") + ": no such mesh file"),
            std::string::npos)
      << e;
  e = error_of(test::replace_once(text, "translation = [\"51 mm\", \"0 mm\", \"12 mm\"]",
                                  "translation = [\"51 mm\", \"0 mm\"]"));
  EXPECT_NE(e.find("key 'geometry.part[3].translation' = 2 values: expected three values (x, y, z)"), std::string::npos)
      << e;
  e = error_of(test::replace_once(text, "unit = \"mm\"", "unit = \"ft\""));
  EXPECT_NE(e.find("key 'geometry.part[0].unit'"), std::string::npos) << e;
  e = error_of(test::replace_once(text, "name = \"hub\"", "name = \"rotor_disk\""));
  EXPECT_NE(e.find("key 'geometry.part[1].name' = \"rotor_disk\": expected a name no other part has"),
            std::string::npos)
      << e;
  e = error_of(test::replace_once(text, "density = \"7850 kg/m^3\"", "density = \"7850 kg\""));
  EXPECT_NE(e.find("key 'geometry.part[1].density'"), std::string::npos) << e;
  e = error_of(test::replace_once(text, "tolerance = 0.0005", "tolerance = 0.0005\nsize = 2"));
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
}

}  // namespace
}  // namespace poise::engine
