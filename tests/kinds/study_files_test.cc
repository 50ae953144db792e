// Strict study and model files: every documented refusal, with its message naming
// file, line, key, value and what was expected.
#include <gtest/gtest.h>

#include <filesystem>

#include "model_files/seeker_model.h"
#include "engine/study_files/study_config.h"
#include "engine/run/study_runner.h"
#include "engine/study_files/toml_reader.h"
#include "kinds/seeker_los/seeker_los_sections.h"
#include "test_util.h"

using namespace poise::kinds::seeker_los;  // the kinds' and model files' own namespaces
using namespace poise::model_files;  // the kinds' and model files' own namespaces

namespace poise::engine {
namespace {

using test::TempDir;

const std::string kModel = "models/seeker_two_axis_wang2011.toml";

// Writes the repository's model with one edit and returns the error message of loading it.
std::string model_error(const TempDir& dir, const std::string& from, const std::string& to) {
  const std::string text = test::replace_once(test::read_text(test::source_path(kModel)), from, to);
  const std::string path = dir.file("model.toml");
  test::write_text(path, text);
  try {
    load_seeker_model(path);
  } catch (const ValidationError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string study_text() {
  return R"([study]
name = "t"
kind = "seeker_los"
model = "model.toml"

[sampling]
method = "sobol"
samples = 64
seed = 1

[grid]
yaw_points = 5
pitch_points = 5

[requirement]
los_error = "1 px"
)";
}

std::string study_error(const TempDir& dir, const std::string& text) {
  test::write_text(dir.file("model.toml"), test::read_text(test::source_path(kModel)));
  test::write_text(dir.file("study.toml"), text);
  try {
    load_study(dir.file("study.toml"));
  } catch (const ValidationError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ModelFile, RepositoryModelLoads) {
  const SeekerModel m = load_seeker_model(test::source_path(kModel));
  EXPECT_DOUBLE_EQ(m.yaw.span, 0.082);
  EXPECT_DOUBLE_EQ(m.pitch.span, 0.056);
  EXPECT_EQ(m.yaw.bearing_sources.size(), 6u);
  EXPECT_NEAR(m.pixel_ifov * 206264.80624709636, 18.75, 1e-9);
}

TEST(ModelFile, MissingUnit) {
  TempDir d;
  const std::string e = model_error(d, "bearing_span = \"82 mm\"", "bearing_span = \"82\"");
  EXPECT_NE(e.find("model.toml:"), std::string::npos) << e;
  EXPECT_NE(e.find("key 'yaw.bearing_span' = \"82\""), std::string::npos) << e;
  EXPECT_NE(e.find("expected a length, e.g. \"1 mm\" (missing unit)"), std::string::npos) << e;
}

TEST(ModelFile, BareNumberNamesTheMissingUnit) {
  TempDir d;
  const std::string e = model_error(d, "bearing_span = \"82 mm\"", "bearing_span = 82");
  EXPECT_NE(e.find("key 'yaw.bearing_span' = 82: expected a length with its unit in quotes"),
            std::string::npos) << e;
}

TEST(ModelFile, WrongUnit) {
  TempDir d;
  const std::string e = model_error(d, "bearing_span = \"82 mm\"", "bearing_span = \"82 deg\"");
  EXPECT_NE(e.find("key 'yaw.bearing_span' = \"82 deg\": expected a length, e.g. \"1 mm\" (wrong unit: got an angle)"),
            std::string::npos) << e;
}

TEST(ModelFile, LineNumberOfTheBadValue) {
  TempDir d;
  const std::string text = test::read_text(test::source_path(kModel));
  const auto pos = text.find("bearing_span = \"56 mm\"");
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(pos), '\n'));
  const std::string e = model_error(d, "bearing_span = \"56 mm\"", "bearing_span = \"56 kg\"");
  EXPECT_NE(e.find("model.toml:" + std::to_string(line) + ":"), std::string::npos) << e;
  EXPECT_NE(e.find("pitch.bearing_span"), std::string::npos) << e;
}

TEST(ModelFile, NonPhysicalValue) {
  TempDir d;
  const std::string e = model_error(d, "bearing_span = \"82 mm\"", "bearing_span = \"-82 mm\"");
  EXPECT_NE(e.find("key 'yaw.bearing_span' = \"-82 mm\": expected a positive value"), std::string::npos) << e;
  const std::string e2 = model_error(d, "tolerance = \"0.0025 mm\"", "tolerance = \"-0.0025 mm\"");
  EXPECT_NE(e2.find("yaw.radial_runout.tolerance"), std::string::npos) << e2;
  EXPECT_NE(e2.find("a value >= 0"), std::string::npos) << e2;
}

TEST(ModelFile, UnknownKey) {
  TempDir d;
  const std::string e = model_error(d, "[optics]\n", "[optics]\nbarel_length = \"90 mm\"\n");
  EXPECT_NE(e.find("key 'optics.barel_length' = \"90 mm\": expected no such key here (unknown key"),
            std::string::npos) << e;
}

TEST(ModelFile, UnknownDistributionAndConvention) {
  TempDir d;
  const std::string e = model_error(d, "distribution = \"normal\"", "distribution = \"gaussian\"");
  EXPECT_NE(e.find("key 'yaw.perpendicularity.distribution' = \"gaussian\": expected one of \"normal\", \"uniform\""),
            std::string::npos) << e;
  const std::string e2 = model_error(d, "tolerance_is = \"1sigma\"", "tolerance_is = \"3 sigma\"");
  EXPECT_NE(e2.find("expected one of \"bounds\", \"1sigma\", \"2sigma\", \"3sigma\""), std::string::npos) << e2;
}

TEST(ModelFile, NormalWithBoundsIsRefused) {
  TempDir d;
  const std::string e = model_error(d, "tolerance_is = \"1sigma\"", "tolerance_is = \"bounds\"");
  EXPECT_NE(e.find("a normal distribution has no bounds"), std::string::npos) << e;
}

TEST(ModelFile, MissingKey) {
  TempDir d;
  const std::string e = model_error(d, "barrel_length = \"90 mm\"", "");
  EXPECT_NE(e.find("key 'optics.barrel_length': expected a length with its unit, e.g. \"1 mm\" (missing)"),
            std::string::npos) << e;
}

TEST(ModelFile, ABudgetInAModelIsRefusedWithItsNewHome) {
  // The paper's budget values are a budget file now (poise budget); a model's [declared]
  // table is an unknown key.
  TempDir d;
  const std::string e = model_error(d, "[optics]\n", "[declared]\nsigma_11 = { value = \"10.06 arcsec\" }\n\n[optics]\n");
  EXPECT_NE(e.find("key 'declared"), std::string::npos) << e;
}

TEST(ModelFile, EveryErrorIsReportedAtOnce) {
  TempDir d;
  std::string text = test::read_text(test::source_path(kModel));
  text = test::replace_once(text, "bearing_span = \"82 mm\"", "bearing_span = \"82\"");
  text = test::replace_once(text, "bearing_span = \"56 mm\"", "bearing_span = \"56 s\"");
  test::write_text(d.file("m.toml"), text);
  try {
    load_seeker_model(d.file("m.toml"));
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_EQ(e.errors().size(), 2u) << e.what();
    EXPECT_NE(std::string(e.what()).find("2 errors in the input"), std::string::npos);
  }
}

TEST(ModelFile, OverrideOfUnknownKeyIsRefused) {
  try {
    load_seeker_model(test::source_path(kModel), {{"yaw.bearing_spam", "90 mm"}});
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'yaw.bearing_spam' = \"90 mm\": expected an override of a key that exists"),
              std::string::npos) << e.what();
  }
  const SeekerModel m = load_seeker_model(test::source_path(kModel), {{"yaw.bearing_span", "100 mm"}});
  EXPECT_DOUBLE_EQ(m.yaw.span, 0.1);
}

TEST(ModelFile, TomlSyntaxErrorHasLine) {
  TempDir d;
  test::write_text(d.file("bad.toml"), "[model]\nname = \"x\nkind = 1\n");
  try {
    load_seeker_model(d.file("bad.toml"));
    FAIL() << "no error";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.toml:2:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("valid TOML"), std::string::npos) << e.what();
  }
}

TEST(StudyFile, ValidStudyLoads) {
  TempDir d;
  EXPECT_EQ(study_error(d, study_text()), "(no error)");
  const StudyConfig c = load_study(d.file("study.toml"));
  EXPECT_EQ(c.samples, 64u);
  EXPECT_TRUE(seeker_sections(c).requirement_in_pixels);
  EXPECT_DOUBLE_EQ(seeker_sections(c).requirement, 1.0);
}

TEST(StudyFile, UnknownKeyWithLine) {
  TempDir d;
  const std::string e = study_error(d, test::replace_once(study_text(), "seed = 1", "seed = 1\nsamplez = 10"));
  EXPECT_NE(e.find("study.toml:10:11: key 'sampling.samplez' = 10: expected no such key here"), std::string::npos) << e;
}

TEST(StudyFile, UnknownSection) {
  TempDir d;
  const std::string e = study_error(d, study_text() + "\n[outputs]\nplots = true\n");
  EXPECT_NE(e.find("key 'outputs'"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
}

TEST(StudyFile, SampleCountOutOfRange) {
  TempDir d;
  const std::string e = study_error(d, test::replace_once(study_text(), "samples = 64", "samples = 0"));
  EXPECT_NE(e.find("key 'sampling.samples' = 0: expected an integer from 1 to 1000000000"), std::string::npos) << e;
}

TEST(StudyFile, BadMethod) {
  TempDir d;
  const std::string e = study_error(d, test::replace_once(study_text(), "\"sobol\"", "\"halton\""));
  EXPECT_NE(e.find("key 'sampling.method' = \"halton\": expected one of \"sobol\", \"lhs\", \"monte_carlo\""),
            std::string::npos) << e;
}

TEST(StudyFile, RequirementNeedsAngleOrPixels) {
  TempDir d;
  const std::string e = study_error(d, test::replace_once(study_text(), "\"1 px\"", "\"1 kg\""));
  EXPECT_NE(e.find("key 'requirement.los_error' = \"1 kg\": expected a positive angle or pixel count"),
            std::string::npos) << e;
  const std::string e2 = study_error(d, test::replace_once(study_text(), "\"1 px\"", "\"0 arcsec\""));
  EXPECT_NE(e2.find("not positive"), std::string::npos) << e2;
}

TEST(StudyFile, MissingModelFile) {
  TempDir d;
  const std::string e = study_error(d, test::replace_once(study_text(), "model.toml", "nope.toml"));
  EXPECT_NE(e.find("key 'study.model' = \"nope.toml\": expected an existing model file"), std::string::npos) << e;
}

TEST(StudyFile, MissingSection) {
  TempDir d;
  const std::string e = study_error(d, test::replace_once(study_text(), "[grid]\nyaw_points = 5\npitch_points = 5\n", ""));
  EXPECT_NE(e.find("key 'grid': expected a table [grid] (missing)"), std::string::npos) << e;
}

// Every study in the repository, with its model, passes validation (a study file a change
// broke is found here, not by the user).
TEST(StudyFile, EveryRepositoryStudyValidates) {
  std::size_t n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::source_path("studies"))) {
    if (entry.path().extension() != ".toml") continue;
    if (test::read_text(entry.path().string()).find("[optimization]") != std::string::npos) continue;  // poise optimize
    if (test::read_text(entry.path().string()).find("\n[budget]") != std::string::npos) continue;  // poise budget
    ++n;
    try {
      const std::string summary = validate_study(entry.path().string());
      EXPECT_NE(summary.find("valid"), std::string::npos) << summary;
    } catch (const ValidationError& e) {
      ADD_FAILURE() << entry.path() << ": " << e.what();
    }
  }
  EXPECT_GE(n, 7u);  // LOS, three gimbal and three balancing-machine studies at least
}

}  // namespace
}  // namespace poise::engine
