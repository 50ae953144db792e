// A seeker study takes the requirement every kind takes (issue 52): [[requirement]] tables alone,
// or no requirement at all, as the guide documents for every kind; the [requirement] los_error
// shorthand stays.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include <nlohmann/json.hpp>

#include "test_util.h"

namespace poise {
namespace {
using test::read_text;
using test::source_path;
using test::TempDir;

// The shipped seeker study without its sweeps and contribution reruns, its [requirement]
// shorthand replaced by `requirement` (the model by absolute path).
std::string seeker_study(const std::string& requirement) {
  std::string text = read_text(source_path("studies/los_seeker_wang2011.toml"));
  if (const std::size_t sweeps = text.find("[[sweep]]"); sweeps != std::string::npos) text.erase(sweeps);
  std::string models = "\"";  // (appended: g++ 12 warns falsely on "\"" + a string)
  models.append(source_path("models")).append("/");
  text = test::replace_once(text, "\"../models/", models);
  const std::size_t at = text.find("[requirement]");
  const std::size_t end = std::min(text.find("\n[", at + 1), text.size());
  std::string out = text.substr(0, at);
  out.append(requirement).append(text, end, std::string::npos).append("\n[output]\ncontribution_samples = 0\n");
  return out;
}

nlohmann::json run(TempDir& dir, const std::string& requirement) {
  test::write_text(dir.file("s.toml"), seeker_study(requirement));
  const auto v = test::run_poise(dir, "validate '" + dir.file("s.toml") + "'");
  EXPECT_EQ(v.status, 0) << v.err;
  const auto r = test::run_poise(dir, "run '" + dir.file("s.toml") + "' --samples 8 --threads 2 -q --no-plots --out '" +
                                          dir.file("run") + "'");
  EXPECT_EQ(r.status, 0) << r.err;
  return nlohmann::json::parse(read_text(dir.file("run") + "/summary.json"));
}

TEST(SeekerRequirement, RequirementTablesAloneAreTheStudysRequirements) {
  TempDir dir;
  const auto s =
      run(dir, "[[requirement]]\noutput = \"los_max_px\"\nstatistic = \"p95\"\nat_most = \"5 px\"\n");
  ASSERT_EQ(s["requirements"].size(), 1u);
  EXPECT_EQ(s["requirements"][0]["output"], "los_max_px");
  EXPECT_EQ(s["requirements"][0]["statistic"], "p95");
  EXPECT_EQ(s["details"]["requirement"]["as_written"], "5 px");  // the field figures' limit
}

TEST(SeekerRequirement, AStudyWithoutRequirementRunsAndSaysSo) {
  TempDir dir;
  const auto s = run(dir, "");
  EXPECT_TRUE(s["requirements"].empty());
  EXPECT_EQ(s["answer"].get<std::string>().rfind("No requirement is declared", 0), 0u) << s["answer"];
}

}  // namespace
}  // namespace poise
