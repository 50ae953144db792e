// A resumed run computes only the samples it lacks (issue 52): a run stopped by SIGINT in
// process (held at a sample until the signal: it cannot finish first, whatever the machine),
// then --resume, counted by engine::samples_computed(); the resumed folder equals an
// uninterrupted run's (samples.csv byte for byte, summary.json, the seeker's grid values in
// samples.h5). For the seeker (its field sink) and for one procedure kind (the gimbal test).
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <thread>

#include <nlohmann/json.hpp>

#include "engine/results/fault_injection.h"
#include "engine/results/wide_columns.h"
#include "engine/run/sample_driver.h"
#include "engine/run/study_runner.h"
#include "study_run_options.h"
#include "test_util.h"

namespace poise::engine {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using test::TempDir;

// The shipped LOS study without its sweeps and contributions (not under test: short runs).
std::string seeker_study(const TempDir& d) {
  std::string text = test::read_text(test::source_path("studies/los_seeker_wang2011.toml"));
  text = test::replace_once(text, "model = \"../models/", "model = \"" + test::source_path("models") + "/");
  const auto sweep = text.find("[[sweep]]");
  if (sweep != std::string::npos) text.resize(sweep);
  text += "\n[output]\ncontribution_samples = 0\nplots = false\n";
  const std::string p = d.file("seeker.toml");
  test::write_text(p, text);
  return p;
}

RunOptions options(const std::string& out, std::size_t samples) {
  RunOptions o = test::quiet_run_options(out, 2);
  o.samples = samples;
  return o;
}

// Runs the study into `out`, held at sample `hold_at` until this test's SIGINT stops it; returns
// the samples it finished (samples.csv's rows).
std::size_t interrupted_run(const std::string& study, const std::string& out, std::size_t samples,
                            std::size_t hold_at) {
  fault_injection::hold_at_sample(hold_at);
  std::thread signaller([] {
    while (!fault_injection::hold_reached()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    std::raise(SIGINT);  // the run's InterruptGuard turns it into a clean stop
  });
  EXPECT_THROW(run_study(study, options(out, samples)), Interrupted);
  signaller.join();
  fault_injection::hold_at_sample(std::nullopt);
  const std::string csv = test::read_text(out + "/samples.csv");
  return static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')) - 1;
}

// Resumes `dir`; returns the samples computed meanwhile.
std::size_t computed_by_resume(const std::string& study, const std::string& dir) {
  RunOptions o = test::quiet_run_options("", 2);
  o.resume = dir;
  samples_computed() = 0;
  run_study(study, o);
  return samples_computed();
}

json comparable(const std::string& dir) {
  json s = json::parse(test::read_text(dir + "/summary.json"));
  s.erase("provenance");
  s["sampling"].erase("threads");
  if (s.contains("solver")) s.erase("solver");
  if (s["samples_h5"].is_object()) s["samples_h5"].erase("file");
  return s;
}

std::vector<std::vector<float>> grid_values(const std::string& dir) {
  const WideColumnsReader r(dir + "/samples.h5", "grid_total_arcsec");
  std::vector<std::vector<float>> columns(r.columns());
  for (std::size_t p = 0; p < columns.size(); ++p) r.read_column(p, columns[p]);
  return columns;
}

TEST(ResumeComputes, SeekerOnlyTheSamplesItLacks) {
  TempDir d;
  const std::string study = seeker_study(d);
  constexpr std::size_t kSamples = 8192;
  // Held at sample 2048 (chunks of [output] block = 1024): at least the two chunks before it are
  // written before the run stops.
  const std::size_t done = interrupted_run(study, d.file("cut"), kSamples, 2048);
  ASSERT_GE(done, 2048u);
  ASSERT_LT(done, kSamples);
  fs::copy(d.file("cut"), d.file("lost"));
  fs::remove(d.file("lost/samples.h5"));  // as after kill -9 before samples.h5 was closed

  EXPECT_EQ(computed_by_resume(study, d.file("cut")), kSamples - done);
  // Without the interrupted run's grid values the finished samples are computed again (and only
  // then): the maps need their values.
  EXPECT_EQ(computed_by_resume(study, d.file("lost")), kSamples);
  samples_computed() = 0;
  run_study(study, options(d.file("whole"), kSamples));
  EXPECT_EQ(samples_computed(), kSamples);

  for (const char* dir : {"cut", "lost"}) {
    SCOPED_TRACE(dir);
    EXPECT_EQ(test::read_text(d.file(std::string(dir) + "/samples.csv")), test::read_text(d.file("whole/samples.csv")));
    EXPECT_EQ(comparable(d.file(dir)), comparable(d.file("whole")));
    EXPECT_EQ(grid_values(d.file(dir)), grid_values(d.file("whole")));
    EXPECT_FALSE(fs::exists(d.file(std::string(dir) + "/samples.h5.interrupted")));
  }
  EXPECT_GT(json::parse(test::read_text(d.file("whole/summary.json")))["details"]["pooled_field_arcsec"]["p95"]["value"]
                .get<double>(),
            0.0);
}

TEST(ResumeComputes, GimbalTestOnlyTheSamplesItLacks) {
  TempDir d;
  const std::string study = test::source_path("studies/gimbal_unbalance_mc.toml");
  constexpr std::size_t kSamples = 48;
  const std::size_t done = interrupted_run(study, d.file("cut"), kSamples, 24);  // chunks of 8
  ASSERT_GE(done, 16u);
  ASSERT_LT(done, kSamples);
  EXPECT_EQ(computed_by_resume(study, d.file("cut")), kSamples - done);
  run_study(study, options(d.file("whole"), kSamples));
  EXPECT_EQ(test::read_text(d.file("cut/samples.csv")), test::read_text(d.file("whole/samples.csv")));
  json cut = comparable(d.file("cut")), whole = comparable(d.file("whole"));
  EXPECT_EQ(cut, whole);
}

}  // namespace
}  // namespace poise::engine
