// Every shipped study run at a fixed seed and a small sample count gives the samples.csv
// recorded in tests/data/study_reference/ (record.sh, plan.txt): a refactoring of the engine
// or of a kind's module changes no result.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/provenance.h"
#include "test_util.h"

namespace poise {
namespace {
namespace fs = std::filesystem;
using test::read_text;
using test::source_path;
using test::TempDir;

struct PlannedRun {
  std::string study;
  std::string samples, seed;
};

std::vector<PlannedRun> plan() {
  std::vector<PlannedRun> out;
  std::ifstream in(source_path("tests/data/study_reference/plan.txt"));
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    PlannedRun r;
    ss >> r.study >> r.samples >> r.seed;
    if (!r.study.empty()) out.push_back(r);
  }
  return out;
}

TEST(StudyReference, EveryShippedStudyIsInThePlan) {
  std::set<std::string> planned;
  for (const auto& r : plan()) planned.insert(r.study);
  std::size_t studies = 0;
  for (const auto& e : fs::directory_iterator(source_path("studies"))) {
    if (e.path().extension() != ".toml") continue;
    if (read_text(e.path().string()).find("\n[study]") == std::string::npos) continue;  // an optimization file
    ++studies;
    EXPECT_TRUE(planned.count(e.path().stem().string())) << e.path() << " has no recorded reference (plan.txt)";
  }
  EXPECT_GE(studies, 10u);
}

class StudyReferenceRun : public ::testing::TestWithParam<PlannedRun> {};

TEST_P(StudyReferenceRun, SamplesEqualTheRecordedOnes) {
  const PlannedRun& r = GetParam();
  TempDir dir;
  const std::string out = dir.file("run");
  const auto res = test::run_poise(dir, "run '" + source_path("studies/" + r.study + ".toml") + "' --samples " +
                                            r.samples + " --seed " + r.seed + " --threads 2 --quiet --no-plots --out '" +
                                            out + "'");
  ASSERT_EQ(res.status, 0) << res.err;
  const std::string ref = source_path("tests/data/study_reference/" + r.study);
  // samples.h5 (the per-sample grid values of a LOS study): the digest of its values.
  if (fs::exists(ref + ".h5.digest")) {
    std::string want = read_text(ref + ".h5.digest");
    want.erase(want.find_last_not_of(" \n") + 1);
    const auto summary = nlohmann::json::parse(read_text(out + "/summary.json"));
    EXPECT_EQ(summary["samples_h5"]["values_digest"], want) << r.study << ": the values of samples.h5 differ from the recorded ones";
  } else {
    EXPECT_FALSE(fs::exists(out + "/samples.h5")) << r.study << " writes samples.h5: record its digest (record.sh)";
  }
  if (fs::exists(ref + ".sha1")) {  // a large samples.csv is recorded as its SHA-1
    std::string want = read_text(ref + ".sha1");
    want.erase(want.find_last_not_of(" \n") + 1);
    EXPECT_EQ(studies::file_sha1(out + "/samples.csv"), want) << r.study << ": samples.csv differs from the recorded reference";
    return;
  }
  const std::string want = read_text(ref + ".csv");
  ASSERT_FALSE(want.empty()) << "no reference recorded for " << r.study;
  EXPECT_EQ(read_text(out + "/samples.csv"), want) << r.study << ": samples.csv differs from the recorded reference";
}

INSTANTIATE_TEST_SUITE_P(Shipped, StudyReferenceRun, ::testing::ValuesIn(plan()),
                         [](const ::testing::TestParamInfo<PlannedRun>& run) { return run.param.study; });

}  // namespace
}  // namespace poise
