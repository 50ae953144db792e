// A misspelled name in a study file gets one error that names the nearest right one: a study
// kind, a requirement's output, a sweep's model key (once for the sweep, not once per value).
#include <gtest/gtest.h>

#include <string>

#include "core/nearest_name.h"
#include "test_util.h"

namespace poise {
namespace {

// The shipped shaft_sag study with `from` replaced by `to`, validated: exit status and stderr.
test::RunResult validate_with(const test::TempDir& d, const std::string& from, const std::string& to) {
  std::string text = test::read_text(test::source_path("studies/shaft_sag_example.toml"));
  text = test::replace_once(text, "model = \"../models/", "model = \"" + test::source_path("models") + "/");
  test::write_text(d.file("s.toml"), test::replace_once(text, from, to));
  return test::run_poise(d, "validate '" + d.file("s.toml") + "'");
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(DidYouMean, NearestNameByEditDistance) {
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(nearest_name("los_eror_arcsec", {"tilt_urad", "los_error_arcsec", "deflection_um"}), "los_error_arcsec");
  EXPECT_EQ(nearest_name("pressure", {"tilt_urad", "los_error_arcsec"}), "");  // nothing close: no guess
  EXPECT_EQ(did_you_mean("spam", {"span"}), "; did you mean 'span'?");
}

TEST(DidYouMean, StudyKind) {
  test::TempDir d;
  const auto r = validate_with(d, "kind = \"shaft_sag\"", "kind = \"shaft_sagg\"");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("did you mean 'shaft_sag'?"), std::string::npos) << r.err;
}

TEST(DidYouMean, RequirementOutput) {
  test::TempDir d;
  const auto r = validate_with(d, "output = \"los_error_arcsec\"", "output = \"los_eror_arcsec\"");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("did you mean 'los_error_arcsec'?"), std::string::npos) << r.err;
}

TEST(DidYouMean, SweepKeySaidOnce) {
  test::TempDir d;
  const auto r = validate_with(d, "parameter = \"parameters.load_position\"", "parameter = \"parameters.load_positon\"");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(count(r.err, "did you mean 'parameters.load_position'?"), 1u) << r.err;
  EXPECT_NE(r.err.find("1 error"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace poise
