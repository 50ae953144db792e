// Every shipped study run at a fixed seed and a small sample count gives the samples.csv
// recorded in tests/data/study_reference/ (record.sh, plan.txt): a refactoring of the engine
// or of a kind's module changes no result.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <ostream>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/results/provenance.h"
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
// gtest prints a parameter in a test's name line: the study, not the struct's bytes.
void PrintTo(const PlannedRun& r, std::ostream* os) { *os << r.study << " (" << r.samples << " samples, seed " << r.seed << ")"; }

// Every shipped study (studies/*.toml with a [study] table), at the sample count and seed
// plan.txt gives it, else 2 samples at seed 11: a new study enters the test by its file alone.
std::vector<PlannedRun> plan() {
  std::map<std::string, PlannedRun> planned;
  std::ifstream in(source_path("tests/data/study_reference/plan.txt"));
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    PlannedRun r;
    ss >> r.study >> r.samples >> r.seed;
    if (!r.study.empty()) planned[r.study] = r;
  }
  std::vector<PlannedRun> out;
  for (const auto& e : fs::directory_iterator(source_path("studies"))) {
    if (e.path().extension() != ".toml") continue;
    if (read_text(e.path().string()).find("\n[study]") == std::string::npos) continue;  // an optimization file
    const std::string study = e.path().stem().string();
    const auto it = planned.find(study);
    out.push_back(it != planned.end() ? it->second : PlannedRun{study, "2", "11"});
  }
  std::sort(out.begin(), out.end(), [](const PlannedRun& a, const PlannedRun& b) { return a.study < b.study; });
  return out;
}

TEST(StudyReference, EveryShippedStudyHasAReference) {
  std::size_t studies = 0;
  for (const auto& r : plan()) {
    ++studies;
    const std::string ref = source_path("tests/data/study_reference/" + r.study);
    EXPECT_TRUE(fs::exists(ref + ".csv") || fs::exists(ref + ".sha1"))
        << r.study << " has no recorded reference: tests/data/study_reference/record.sh build/poise " << r.study;
  }
  EXPECT_GE(studies, 10u);
}

class StudyReferenceRun : public ::testing::TestWithParam<PlannedRun> {};

TEST_P(StudyReferenceRun, SamplesEqualTheRecordedOnes) {
  const PlannedRun& r = GetParam();
  if (read_text(source_path("studies/" + r.study + ".toml")).find("\nkind = \"python\"") != std::string::npos) {
    GTEST_SKIP() << r.study << ": a Python function's study runs from Python; python/tests/test_poise.py checks it";
  }
  TempDir dir;
  const std::string out = dir.file("run");
  const auto res = test::run_poise(dir, "run '" + source_path("studies/" + r.study + ".toml") + "' --samples " +
                                            r.samples + " --seed " + r.seed + " --threads 2 --allow-programs --quiet --no-plots --out '" +
                                            out + "'");
  ASSERT_EQ(res.status, 0) << res.err;
  const std::string ref = source_path("tests/data/study_reference/" + r.study);
  // samples.h5 (the per-sample grid values of a LOS study): the digest of its values.
  if (fs::exists(ref + ".h5.digest")) {
    std::string want = read_text(ref + ".h5.digest");
    want.erase(want.find_last_not_of(" \n") + 1);
    const auto summary = nlohmann::json::parse(read_text(out + "/summary.json"));
    EXPECT_EQ(summary["samples_h5"]["values_digest"], want) << r.study << ": the values of samples.h5 differ from the recorded ones";
  } else if (fs::exists(out + "/samples.h5")) {
    // samples.h5 of a study without wide values holds samples.csv's columns (compared below).
    const auto summary = nlohmann::json::parse(read_text(out + "/summary.json"));
    EXPECT_FALSE(summary["samples_h5"].contains("values_digest")) << r.study << " writes wide values: record their digest (record.sh)";
  }
  if (fs::exists(ref + ".sha1")) {  // a large samples.csv is recorded as its SHA-1
    std::string want = read_text(ref + ".sha1");
    want.erase(want.find_last_not_of(" \n") + 1);
    EXPECT_EQ(engine::file_sha1(out + "/samples.csv"), want) << r.study << ": samples.csv differs from the recorded reference";
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
