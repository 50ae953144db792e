// `--until` on a quantile refuses a replicate design that cannot support its interval (issue
// 21): fewer than 10 samples per replicate beyond the quantile. Exit status 2, the reason and
// the replicate size that would do, and no result folder; a design that can support it runs;
// summary.json marks one-sided and approximate intervals with "ci95_note".
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/run/convergence.h"
#include "core/error.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using poise::test::run_poise;
using poise::test::source_path;
using poise::test::TempDir;

std::string quoted(const std::string& s) { return "'" + s + "'"; }

TEST(UntilTailDesign, CheckNamesTheReplicateSizeThatWouldDo) {
  const std::vector<std::string> outputs = {"los_max_arcsec"};
  const auto p9973 = poise::engine::parse_until("los_max_arcsec.p99_73<=0.5", outputs);
  try {
    poise::engine::check_until_design(p9973, 1024);
    FAIL() << "accepted p99_73 on replicates of 1024";
  } catch (const poise::UsageError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("replicates of 1024 samples cannot support an interval on p99_73"), std::string::npos) << m;
    EXPECT_NE(m.find("about 2.765 samples beyond it"), std::string::npos) << m;
    EXPECT_NE(m.find("replicate_size to at least 3704"), std::string::npos) << m;
  }
  EXPECT_NO_THROW(poise::engine::check_until_design(p9973, 4096));  // 11.06 beyond
  EXPECT_NO_THROW(poise::engine::check_until_design(p9973, 0));     // Monte Carlo: order statistics
  const auto p95 = poise::engine::parse_until("los_max_arcsec.p95<=1", outputs);
  EXPECT_THROW(poise::engine::check_until_design(p95, 128), poise::UsageError);  // 6.4 beyond
  EXPECT_NO_THROW(poise::engine::check_until_design(p95, 256));                 // 12.8
  const auto mean = poise::engine::parse_until("los_max_arcsec.mean<=1", outputs);
  EXPECT_NO_THROW(poise::engine::check_until_design(mean, 2));
}

TEST(UntilTailDesign, RefusedBeforeTheResultFolderExists) {
  TempDir d;
  const std::string study = quoted(source_path("studies/los_seeker_wang2011_replicates.toml"));
  const auto r = run_poise(d, "run " + study + " --until 'los_max_arcsec.p99_73<=0.5' -q --no-plots --results-root " +
                                  quoted(d.file("results")) + " --out " + quoted(d.file("u")));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("cannot support an interval on p99_73"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d.file("u")));
  EXPECT_FALSE(fs::exists(d.file("results")));
}

TEST(UntilTailDesign, SummaryMarksOneSidedAndApproximateIntervals) {
  TempDir d;
  // 2048 samples in 2 replicates of 1024: p99.73 has 2.8 samples per replicate beyond it.
  const std::string study = quoted(source_path("studies/los_seeker_wang2011_replicates.toml"));
  auto r = run_poise(d, "run " + study + " --samples 2048 -q --no-plots --out " + quoted(d.file("rep")));
  ASSERT_EQ(r.status, 0) << r.err;
  const json s = json::parse(poise::test::read_text(d.file("rep/summary.json")));
  const json& p = s["outputs"]["los_max_arcsec"]["p99_73"];
  ASSERT_TRUE(p.contains("ci95_note")) << p.dump();
  EXPECT_NE(p["ci95_note"].get<std::string>().find("approximate: replicate_size x (1 - p) = 2.76"), std::string::npos)
      << p.dump();
  // p95: 51 samples per replicate beyond it, not approximate (with 2 replicates, t(0.975, 1) =
  // 12.7 may still push its upper end past the sample: then one-sided, and said so).
  const json& p95 = s["outputs"]["los_max_arcsec"]["p95"];
  EXPECT_EQ(p95.value("ci95_note", "").find("approximate"), std::string::npos) << p95.dump();
  EXPECT_EQ(p95["ci95"][1].is_null(), p95.value("ci95_note", "").rfind("one-sided", 0) == 0) << p95.dump();
  EXPECT_TRUE(s["sample_convergence"]["figures"]["los_max_arcsec"]["p99_73"].contains("ci95_note"));
  // Plain Monte Carlo of 1024: p99.73 has no upper end, said as such.
  const std::string plain = d.file("plain.toml");
  std::string text = poise::test::read_text(source_path("studies/los_seeker_wang2011_replicates.toml"));
  text = poise::test::replace_once(text, "method = \"sobol\"", "method = \"monte_carlo\"");
  text = poise::test::replace_once(text, "replicate_size = 1024\n", "");
  text = poise::test::replace_once(text, "model = \"../models/", "model = \"" + source_path("models/"));
  poise::test::write_text(plain, text);
  r = run_poise(d, "run " + quoted(plain) + " --samples 1024 -q --no-plots --out " + quoted(d.file("mc")));
  ASSERT_EQ(r.status, 0) << r.err;
  const json m = json::parse(poise::test::read_text(d.file("mc/summary.json")));
  const json& q = m["outputs"]["los_max_arcsec"]["p99_73"];
  EXPECT_TRUE(q["ci95"][0].is_number());
  EXPECT_TRUE(q["ci95"][1].is_null());
  EXPECT_EQ(q["ci95_note"].get<std::string>().rfind("one-sided: no upper bound below n = 1365", 0), 0u) << q.dump();
  const std::string report = poise::test::read_text(d.file("mc/report.html"));
  EXPECT_NE(report.find("one-sided: no upper bound below n = 1365"), std::string::npos);
}

}  // namespace
