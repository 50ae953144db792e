// The geometry studies end to end (small runs): geometry_mass_properties on the simulator disk,
// los_obstruction on the Wang 2011 seeker, the LOS study's clearance output for the span sizing;
// strict files; same samples for any thread count; replay of one sample.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "model_files/disk_geometry_model.h"
#include "engine/study_files/study_config.h"
#include "engine/results/result_io.h"
#include "engine/kind_interface/study_evaluation.h"
#include "engine/run/study_runner.h"
#include "study_run_options.h"
#include "test_util.h"

using namespace poise::model_files;  // the kinds' and model files' own namespaces

namespace poise::engine {
namespace {

using nlohmann::json;

json read_json(const std::string& path) { return json::parse(test::read_text(path)); }

// A copy of a repository study next to a copy of its model, with edits.
std::string small_study(const test::TempDir& d, const std::string& study, const std::string& model,
                        const std::vector<std::pair<std::string, std::string>>& edits) {
  std::string text = test::read_text(test::source_path("studies/" + study));
  text = test::replace_once(text, "\"../models/" + model + "\"", "\"" + model + "\"");
  for (const auto& [from, to] : edits) text = test::replace_once(text, from, to);
  test::write_text(d.file(study), text);
  test::write_text(d.file(model), test::read_text(test::source_path("models/" + model)));
  return d.file(study);
}

std::string mass_study(const test::TempDir& d) {
  return small_study(d, "geometry_mass_properties.toml", "simulator_disk_yang2015.toml",
                     {{"rays_per_side = 200", "rays_per_side = 40"}, {"[25, 50, 100, 200, 400]", "[20, 40]"}});
}

TEST(GeometryStudies, MassPropertiesRunAgreesWithTheClosedForm) {
  test::TempDir d;
  const std::string study = mass_study(d);
  RunOptions o = test::quiet_run_options(d.file("run1"), 1);
  o.samples = 4;
  const std::string dir = run_study(study, o);
  const json s = read_json(dir + "/summary.json");
  const auto& cf = s["details"]["nominal"]["closed_form_check"];
  for (const char* q : {"mass_kg", "e_m", "Jzz_kgm2"}) {
    EXPECT_LT(std::abs(cf[q]["exact_mesh"]["relative_error"].get<double>()), 1e-6) << q;
    EXPECT_LT(std::abs(cf[q]["ray_cast"]["relative_error"].get<double>()), 2e-2) << q;  // 40 rays per side
  }
  // The two clump weights (25.81 g at 45 deg, 15.53 g at 270 deg, on r = 51 mm) set e.
  EXPECT_NEAR(cf["e_m"]["exact_mesh"]["closed_form"].get<double>(), 2.074e-3, 0.005e-3);
  EXPECT_EQ(s["details"]["convergence"].size(), 2u);
  EXPECT_EQ(s["outputs"]["e_um"]["n"].get<int>(), 4);
  EXPECT_TRUE(std::filesystem::exists(dir + "/nominal_disk.stl"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/report.html"));
  // Two threads: the same samples.csv; replay: the same row.
  RunOptions o2 = test::quiet_run_options(d.file("run2"), 2);
  o2.samples = 4;
  const std::string dir2 = run_study(study, o2);
  EXPECT_EQ(test::read_text(dir + "/samples.csv"), test::read_text(dir2 + "/samples.csv"));
  RunOptions r;
  r.samples = 4;
  const json one = replay_sample(study, 2, r);
  EXPECT_EQ(one["status"], "ok");
  const double e2 = one["outputs"]["e_um"].get<double>();
  EXPECT_NE(test::read_text(dir + "/samples.csv").find(csv_number(e2)), std::string::npos);
}

TEST(GeometryStudies, StrictDiskModelAndStudy) {
  test::TempDir d;
  std::string study = small_study(d, "geometry_mass_properties.toml", "simulator_disk_yang2015.toml",
                                  {{"grid = \"per_part\"", "grid = \"per_parts\""}});
  try {
    validate_study(study);
    ADD_FAILURE() << "accepted grid = per_parts";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("mass_properties.grid"), std::string::npos) << e.what();
  }
  test::TempDir d2;
  study = small_study(d2, "geometry_mass_properties.toml", "simulator_disk_yang2015.toml", {});
  test::write_text(d2.file("simulator_disk_yang2015.toml"),
                   test::replace_once(test::read_text(d2.file("simulator_disk_yang2015.toml")),
                                      "circle_a_radius = \"51.0 mm\"", "circle_a_radius = \"63 mm\""));
  try {
    validate_study(study);
    ADD_FAILURE() << "accepted holes outside the disk";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("holes.circle_a_radius"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("holes inside the disk"), std::string::npos) << e.what();
  }
}

TEST(GeometryStudies, ObstructionRun) {
  test::TempDir d;
  const std::string study =
      small_study(d, "los_obstruction.toml", "seeker_two_axis_wang2011.toml",
                  {{"yaw_points = 7", "yaw_points = 3"}, {"pitch_points = 7", "pitch_points = 3"}, {"rays = 8192", "rays = 512"}});
  EXPECT_NE(validate_study(study).find("valid"), std::string::npos);
  RunOptions o = test::quiet_run_options(d.file("run"), 2);
  o.samples = 2;
  const std::string dir = run_study(study, o);
  const json s = read_json(dir + "/summary.json");
  const auto& nom = s["details"]["nominal"]["outputs"];
  // The flat window vignettes the field's corners; the centre passes whole.
  EXPECT_LT(nom["min_fraction_pct"].get<double>(), 50.0);
  EXPECT_GT(nom["full_field_pct"].get<double>(), 0.0);
  // The least clearance: the barrel pitching under the ring's top member (1.41 mm, see
  // geometry_obstruction_test), the shafting tolerances move it by far less than a micrometre.
  EXPECT_NEAR(nom["min_clearance_mm"].get<double>(), 1.41, 0.02);
  EXPECT_LT(std::abs(s["outputs"]["clearance_shift_um"]["max"]["value"].get<double>()), 1.0);
  RunOptions r;
  r.samples = 2;
  EXPECT_EQ(replay_sample(study, 1, r)["status"], "ok");
}

TEST(GeometryStudies, ObstructionNeedsAModelWithGeometry) {
  test::TempDir d;
  const std::string study = small_study(d, "los_obstruction.toml", "seeker_two_axis_wang2011.toml", {});
  const std::string model = test::read_text(d.file("seeker_two_axis_wang2011.toml"));
  test::write_text(d.file("seeker_two_axis_wang2011.toml"), model.substr(0, model.find("\n[geometry]")));
  try {
    validate_study(study);
    ADD_FAILURE() << "accepted a model without [geometry]";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("a seeker model with a [geometry] section"), std::string::npos) << e.what();
  }
}

TEST(GeometryStudies, ClearanceOutputFollowsTheSpans) {
  const StudyConfig cfg = load_study(test::source_path("studies/los_seeker_wang2011_housing.toml"));
  const auto names = study_output_names(cfg);
  ASSERT_EQ(names.back(), "min_clearance_mm");
  const auto at = [&](const char* yaw, const char* pitch) {
    const McResult e =
        evaluate_study(cfg, {{"yaw.bearing_span", yaw}, {"pitch.bearing_span", pitch}}, 16, 1, 1);
    return e.values[e.index("min_clearance_mm")].front();
  };
  EXPECT_NEAR(at("82 mm", "56 mm"), 1.41, 0.02);    // the paper's spans: barrel under the ring
  EXPECT_LT(at("131 mm", "144 mm"), 0.0);           // the LOS-only optimum does not fit the housing
  EXPECT_LT(at("70 mm", "56 mm"), 0.0);             // a short ring hits the pitching barrel
}

}  // namespace
}  // namespace poise::engine
