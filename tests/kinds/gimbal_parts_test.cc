// The gimbal rotor as a designer's parts ([[geometry.part]] in a gimbal model, issue 17): the
// as-built parts' unbalance, mass and inertia about the gimbal axis enter each sample in closed
// form; the parts path equals the disk_model path for the same disk; refusals with file, line,
// key and exit status 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "geometry/generators.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_io.h"
#include "model_files/gimbal_model.h"
#include "kinds/gimbal_static_unbalance/gimbal_study.h"
#include "engine/study_files/study_config.h"
#include "engine/study_files/toml_reader.h"
#include "test_util.h"

using namespace poise::kinds::gimbal_static_unbalance;  // the kinds' and model files' own namespaces
using namespace poise::model_files;  // the kinds' and model files' own namespaces

namespace poise::engine {
namespace {

using test::TempDir;
constexpr double kPi = std::numbers::pi;

// Disk (tube) 8..60 mm x 10 mm of aluminium, and a steel cylinder r 6 mm x 8 mm placed off the
// axis by `offset` (x) with a position tolerance: meshes of equal-area polygons (generators.h).
constexpr double kDiskRin = 0.008, kDiskRout = 0.060, kDiskT = 0.010, kDiskRho = 2700;
constexpr double kClumpR = 0.006, kClumpH = 0.008, kClumpRho = 7850;
constexpr int kSegments = 64;

// Polar second moment of area of the regular n-gon with the area of the circle of radius r
// (circumradius R = r sqrt((2 pi / n) / sin(2 pi / n))): A R^2 (2 + cos(2 pi / n)) / 6.
double polygon_polar_moment(double r, int n) {
  const double a = 2 * kPi / n, area = kPi * r * r, big_r2 = r * r * a / std::sin(a);
  return area * big_r2 * (2 + std::cos(a)) / 6;
}

const std::string kParts = R"(
[[geometry.part]]
name = "disk"
mesh = "meshes/disk.stl"
unit = "mm"
density = "2700 kg/m^3"

[[geometry.part]]
name = "clump"
mesh = "meshes/clump.obj"
unit = "mm"
density = "7850 kg/m^3"
translation = ["OFFSET", "0 mm", "10 mm"]
[geometry.part.tolerances.position]
tolerance = "0.5 mm"
distribution = "uniform"
tolerance_is = "bounds"

)";

// A copy of the Yang 2015 rig model in `d` with the parts above (clump at `offset`).
std::string parts_model(const TempDir& d, const std::string& offset, const std::string& parts = kParts) {
  std::filesystem::create_directories(d.file("meshes"));
  geometry::write_stl(geometry::tube(kDiskRin, kDiskRout, 0.0, kDiskT, kSegments, "disk"), d.file("meshes/disk.stl"), 1e-3);
  geometry::write_obj(geometry::cylinder(kClumpR, 0.0, kClumpH, kSegments, "clump"), d.file("meshes/clump.obj"), 1e-3);
  const std::string text = test::read_text(test::source_path("models/gimbal_simulator_yang2015.toml"));
  const std::string path = d.file("rig.toml");
  test::write_text(path, test::replace_once(text, "[counterweight]", test::replace_once(parts, "OFFSET", offset) + "[counterweight]"));
  return path;
}

std::string study_file(const TempDir& d, const std::string& model) {
  const std::string path = d.file("study.toml");
  test::write_text(path, R"([study]
name = "parts"
kind = "gimbal_static_unbalance"
model = ")" + model + R"("

[sampling]
method = "monte_carlo"
samples = 2
seed = 5

[[group]]
name = "g"
positions = 8
repeats = 1

[[group.load]]
mass = "25.81 g"
radius = "51.0 mm"
angle = "0 deg"
)");
  return path;
}

std::size_t column(const std::vector<std::string>& names, const std::string& name) {
  const auto it = std::find(names.begin(), names.end(), name);
  EXPECT_NE(it, names.end()) << name;
  return static_cast<std::size_t>(it - names.begin());
}

// One part translated by a known offset: U = m_c |(e + dx, dy)| exactly (the disk is symmetric),
// mass and inertia about the axis from the polygons' closed forms plus m_c (e + dx)^2 + m_c dy^2.
TEST(GimbalParts, OffsetPartGivesItsUnbalanceMassAndInertia) {
  TempDir d;
  const std::string model_path = parts_model(d, "30 mm");
  const StudyConfig cfg = load_study(study_file(d, model_path));
  const GimbalModel model = load_gimbal_model(cfg.model_path, cfg.overrides);
  ASSERT_TRUE(model.rotor_parts.has_value());
  EXPECT_FALSE(model.disk_geometry.has_value());
  const double m_disk = kDiskRho * kPi * (kDiskRout * kDiskRout - kDiskRin * kDiskRin) * kDiskT;
  const double m_clump = kClumpRho * kPi * kClumpR * kClumpR * kClumpH;
  const double j_disk = kDiskRho * kDiskT * (polygon_polar_moment(kDiskRout, kSegments) - polygon_polar_moment(kDiskRin, kSegments));
  const double j_clump = kClumpRho * kClumpH * polygon_polar_moment(kClumpR, kSegments);
  const double e = 0.030;
  EXPECT_NEAR(model.disk_nominal_mass, m_disk + m_clump, 1e-6 * m_disk);
  EXPECT_NEAR(model.disk_nominal_inertia, j_disk + j_clump + m_clump * e * e, 1e-6 * j_disk);

  const GimbalStudy study(cfg, model, 2, 5);
  const auto& names = study.input_names();
  EXPECT_EQ(names.end() - std::find(names.begin(), names.end(), "part_clump_dx_mm"), 7);  // 3 draws, 4 results
  auto ws = study.make_workspace();
  for (std::size_t i = 0; i < 2; ++i) {
    SampleResult s;
    study.compute(i, *ws, s);
    ASSERT_TRUE(s.ok) << s.message;
    const double dx = s.inputs[column(names, "part_clump_dx_mm")] * 1e-3;
    const double dy = s.inputs[column(names, "part_clump_dy_mm")] * 1e-3;
    EXPECT_GT(std::abs(dx), 0.0);
    const double x = e + dx;
    EXPECT_NEAR(s.inputs[column(names, "parts_unbalance_gmm")] * 1e-6, m_clump * std::hypot(x, dy), 1e-6 * m_clump * e);
    EXPECT_NEAR(s.inputs[column(names, "parts_unbalance_angle_deg")], std::atan2(dy, x) * 180 / kPi, 1e-4);
    EXPECT_NEAR(s.inputs[column(names, "parts_mass_g")] * 1e-3, m_disk + m_clump, 1e-6 * m_disk);
    EXPECT_NEAR(s.inputs[column(names, "parts_inertia_kgm2")], j_disk + j_clump + m_clump * (x * x + dy * dy),
                1e-6 * j_disk);
  }

  // The unbalance reaches the measurement: the same samples with the clump on the axis measure
  // a torque smaller by g m_c e (to the draws' K_T scale errors, about 1%, and the test noise).
  TempDir d0;
  const StudyConfig cfg0 = load_study(study_file(d0, parts_model(d0, "0 mm")));
  const GimbalStudy study0(cfg0, load_gimbal_model(cfg0.model_path), 2, 5);
  auto ws0 = study0.make_workspace();
  const double g_mce = 9.80665 * m_clump * e * 1e3;  // mN*m
  for (std::size_t i = 0; i < 2; ++i) {
    SampleResult s, s0;
    study.compute(i, *ws, s);
    study0.compute(i, *ws0, s0);
    ASSERT_TRUE(s0.ok) << s0.message;
    const std::size_t o = column(study.output_names(), "g_mean_torque_error_mNm");
    EXPECT_NEAR(s.outputs[o] - s0.outputs[o], g_mce, 0.05 * g_mce) << i;
  }
}

// The Yang 2015 disk (without clumps) as the generator's mesh exported to STL and read back as a
// part equals the disk_model path's nominal disk: the same polygons, so the same mass and inertia
// to the float32 rounding of the STL vertices (relative 6e-8 per coordinate: 1e-6 allows for it).
TEST(GimbalParts, PartsEqualTheDiskModelForTheSameDisk) {
  TempDir d;
  std::filesystem::create_directories(d.file("meshes"));
  const std::string yang = test::source_path("models/gimbal_simulator_yang2015.toml");
  const GimbalModel by_disk = load_gimbal_model(yang, {{"geometry.disk_model", "simulator_disk_yang2015.toml"}});
  ASSERT_TRUE(by_disk.disk_geometry.has_value());
  const geometry::Assembly disk = geometry::simulator_disk(by_disk.disk_geometry->nominal);
  ASSERT_EQ(disk.size(), 17u);  // the disk and its 16 holes
  geometry::write_stl(geometry::merge(disk, "disk"), d.file("meshes/yang_disk.stl"), 1e-3);
  const std::string text = test::read_text(yang);
  test::write_text(d.file("rig.toml"), test::replace_once(text, "[counterweight]", R"([[geometry.part]]
name = "disk"
mesh = "meshes/yang_disk.stl"
unit = "mm"
density = "2700 kg/m^3"

[counterweight])"));
  const GimbalModel by_parts = load_gimbal_model(d.file("rig.toml"));
  ASSERT_TRUE(by_parts.rotor_parts.has_value());
  EXPECT_NEAR(by_parts.disk_nominal_mass, by_disk.disk_nominal_mass, 1e-6 * by_disk.disk_nominal_mass);
  EXPECT_NEAR(by_parts.disk_nominal_inertia, by_disk.disk_nominal_inertia, 1e-6 * by_disk.disk_nominal_inertia);
}

TEST(GimbalParts, RefusalsNameTheFileLineAndKey) {
  TempDir d;
  const std::string model = parts_model(d, "30 mm");
  auto refused = [&](const std::string& text, const std::string& expected) {
    test::write_text(d.file("bad.toml"), text);
    test::write_text(d.file("study.toml"), test::replace_once(test::read_text(study_file(d, model)), model, d.file("bad.toml")));
    const test::RunResult r = test::run_poise(d, "validate '" + d.file("study.toml") + "'");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  };
  const std::string good = test::read_text(model);
  // An open mesh, at its key.
  geometry::Mesh open = geometry::cylinder(kClumpR, 0.0, kClumpH, kSegments, "open");
  open.triangles.pop_back();
  geometry::write_obj(open, d.file("meshes/open.obj"), 1e-3);
  const std::size_t line = static_cast<std::size_t>(
      std::count(good.begin(), good.begin() + static_cast<long>(good.find("meshes/clump.obj")), '\n') + 1);
  refused(test::replace_once(good, "meshes/clump.obj", "meshes/open.obj"),
          d.file("bad.toml") + ":" + std::to_string(line) + ":8: key 'geometry.part[1].mesh' = \"meshes/open.obj\": "
          "expected a closed, consistently oriented mesh file (STL or OBJ): " + d.file("meshes/open.obj") + ": not closed");
  // A missing file.
  refused(test::replace_once(good, "meshes/clump.obj", "meshes/none.obj"),
          "key 'geometry.part[1].mesh' = \"meshes/none.obj\": expected a closed, consistently oriented mesh file (STL or "
          "OBJ): " + d.file("meshes/none.obj") + ": no such mesh file");
  // Both a disk model and parts.
  refused(test::replace_once(good, "disk_model = \"\"", "disk_model = \"" + test::source_path("models/simulator_disk_yang2015.toml") + "\""),
          "key 'geometry.disk_model' = \"" + test::source_path("models/simulator_disk_yang2015.toml") +
              "\": expected \"\" when the rotor is given as [[geometry.part]] (one or the other)");
  // Parts heavier than the whole rotor.
  refused(test::replace_once(good, "mass = \"1.5 kg\"", "mass = \"0.2 kg\""),
          "expected parts within the rotor: [rotor] mass (200 g) is the whole rotor as designed, its parts included");
  // Parts whose inertia about the gimbal axis exceeds the whole rotor's.
  refused(test::replace_once(good, "inertia = \"3.5e-3 kg*m^2\"", "inertia = \"1e-4 kg*m^2\""),
          "about the gimbal axis: expected parts within the rotor: [rotor] inertia (");
}

}  // namespace
}  // namespace poise::engine
