// End to end: the default study run small, checked against independent computations:
// thread-count independence, replay of one sample, an independent re-implementation of
// the kinematic chain from the drawn inputs recorded in samples.csv, the summary's
// statistics recomputed from samples.csv, the budget against hand-computed figures.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "engine/run/study_runner.h"
#include "engine/study_files/toml_reader.h"
#include "study_run_options.h"
#include "test_util.h"

namespace poise::engine {
namespace {

using nlohmann::json;
using test::TempDir;
constexpr double kArcsec = 206264.80624709636;
constexpr double kPi = 3.14159265358979323846;

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::size_t col(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return i;
    }
    ADD_FAILURE() << "no column " << name;
    return 0;
  }
  double num(std::size_t row, const std::string& name) const { return std::stod(rows[row][col(name)]); }
};

Csv read_csv(const std::string& path) {
  Csv c;
  std::istringstream in(test::read_text(path));
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    (first ? c.header : c.rows.emplace_back()) = cells;
    first = false;
  }
  return c;
}

// The default study with a small sample count and one short sweep.
std::string small_study(const TempDir& d, const std::string& method = "sobol") {
  std::string text = test::read_text(test::source_path("studies/los_seeker_wang2011.toml"));
  text = test::replace_once(text, "\"../models/", "\"" + test::source_path("models") + "/");
  text = test::replace_once(text, "method = \"sobol\"", "method = \"" + method + "\"");
  text = test::replace_once(text, "samples = 16384", "samples = 300");
  const auto sweep = text.find("[[sweep]]");
  text = text.substr(0, sweep) +
         "[[sweep]]\nparameter = \"yaw.bearing_span\"\nvalues = [\"60 mm\", \"82 mm\"]\nsamples = 64\n";
  const std::string path = d.file("study.toml");
  test::write_text(path, text);
  return path;
}

RunOptions options(const std::string& out, int threads) { return test::quiet_run_options(out, threads); }

TEST(StudyRunner, SamplesIdenticalForOneAndTwoThreads) {
  TempDir d;
  for (const std::string method : {"sobol", "lhs", "monte_carlo"}) {
    const std::string study = small_study(d, method);
    run_study(study, options(d.file(method + "_t1"), 1));
    run_study(study, options(d.file(method + "_t2"), 2));
    const std::string a = test::read_text(d.file(method + "_t1/samples.csv"));
    const std::string b = test::read_text(d.file(method + "_t2/samples.csv"));
    EXPECT_GT(a.size(), 1000u);
    EXPECT_EQ(a, b) << method;
  }
}

TEST(StudyRunner, ReplayOfOneSampleMatchesItsRow) {
  TempDir d;
  const std::string study = small_study(d);
  run_study(study, options(d.file("run"), 2));
  const Csv csv = read_csv(d.file("run/samples.csv"));
  ASSERT_EQ(csv.rows.size(), 300u);
  for (std::size_t i : {0u, 17u, 299u}) {
    const json r = replay_sample(study, i, options("", 1));
    EXPECT_EQ(r["status"], "ok");
    for (const auto& [name, v] : r["outputs"].items()) {
      EXPECT_NEAR(v.get<double>(), csv.num(i, name), 1e-8 * std::max(1.0, std::abs(v.get<double>()))) << name;
    }
    for (const auto& [name, v] : r["inputs"].items()) {
      EXPECT_NEAR(v.get<double>(), csv.num(i, name), 1e-7 * std::max(1.0, std::abs(v.get<double>()))) << name;
    }
    EXPECT_EQ(r["grid"].size(), 169u);
  }
}

// Independent chain: Eigen::AngleAxis rotations about axes built from the recorded inputs.
double independent_los_max_arcsec(const Csv& csv, std::size_t row) {
  struct Src { const char* name; double order; bool scaled; };
  const Src sources[] = {{"radial_runout", 1, true}, {"face_runout", 1, true}, {"clearance", 0, true},
                         {"bore_roundness", 2, true}, {"ball_roundness", 3, false}, {"seat_deformation", 2, false}};
  const double k = csv.num(row, "k_load");
  auto axis_dir = [&](const std::string& axis, double phi, const Eigen::Vector3d& a, const Eigen::Vector3d& e1,
                      const Eigen::Vector3d& e2, double span, Eigen::Vector2d s) {
    Eigen::Vector2d t = s;
    for (const auto& src : sources) {
      for (const std::string b : {"A", "B"}) {
        const double amp = csv.num(row, axis + "_" + src.name + "_" + b + "_um") * 1e-6;
        const double ph = csv.num(row, axis + "_" + src.name + "_" + b + "_phase_deg") * kPi / 180;
        const double sign = b == "A" ? -1.0 : 1.0;
        const double scale = (src.scaled ? k : 1.0) / span;
        t += sign * scale * amp * Eigen::Vector2d(std::cos(src.order * phi + ph), std::sin(src.order * phi + ph));
      }
    }
    return Eigen::Vector3d((a + t[0] * e1 + t[1] * e2).normalized());
  };
  auto frame = [](const Eigen::Vector3d& a, const Eigen::Vector3d& u, double phi) {
    const Eigen::Vector3d c = a.cross(u);
    const double ang = std::atan2(c.norm(), a.dot(u));
    Eigen::Matrix3d tilt = Eigen::Matrix3d::Identity();
    if (c.norm() > 0) tilt = Eigen::AngleAxisd(ang, c.normalized()).toRotationMatrix();
    return Eigen::Matrix3d(tilt * Eigen::AngleAxisd(phi, a).toRotationMatrix());
  };
  const double tilt = csv.num(row, "yaw_perpendicularity_tilt_arcsec") / kArcsec;
  const double az = csv.num(row, "yaw_perpendicularity_azimuth_deg") * kPi / 180;
  const double c2 = csv.num(row, "pitch_perpendicularity_arcsec") / kArcsec;
  const double c3 = csv.num(row, "optics_collimation_arcsec") / kArcsec;
  const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(), Z = Eigen::Vector3d::UnitZ();
  double worst = 0;
  for (int ia = 0; ia < 13; ++ia) {
    for (int ib = 0; ib < 13; ++ib) {
      const double al = (-30.0 + 5.0 * ia) * kPi / 180, be = (-30.0 + 5.0 * ib) * kPi / 180;
      const Eigen::Vector3d u1 = axis_dir("yaw", al, Z, X, Y, 0.082, {tilt * std::cos(az), tilt * std::sin(az)});
      const Eigen::Vector3d u2 = axis_dir("pitch", be, -Y, X, Z, 0.056, {0.0, c2});
      const Eigen::Vector3d d = frame(Z, u1, al) * frame(-Y, u2, be) * Eigen::Vector3d(1, c3, 0).normalized();
      const Eigen::Vector3d n(std::cos(be) * std::cos(al), std::cos(be) * std::sin(al), std::sin(be));
      worst = std::max(worst, std::atan2(d.cross(n).norm(), d.dot(n)));
    }
  }
  return worst * kArcsec;
}

TEST(StudyRunner, DefaultStudyAgainstIndependentFigures) {
  TempDir d;
  const std::string study = small_study(d);
  run_study(study, options(d.file("run"), 2));
  const Csv csv = read_csv(d.file("run/samples.csv"));
  const json s = json::parse(test::read_text(d.file("run/summary.json")));

  // 1. Every 10th sample's greatest LOS error, recomputed by an independent chain.
  for (std::size_t i = 0; i < csv.rows.size(); i += 10) {
    ASSERT_EQ(csv.rows[i][csv.col("status")], "ok");
    EXPECT_NEAR(csv.num(i, "los_max_arcsec"), independent_los_max_arcsec(csv, i), 1e-6) << "sample " << i;
  }
  // 2. The summary's statistics recomputed from samples.csv.
  std::vector<double> v;
  std::size_t meet = 0;
  const double req = s["details"]["requirement"]["arcsec"].get<double>();
  for (std::size_t i = 0; i < csv.rows.size(); ++i) {
    v.push_back(csv.num(i, "los_max_arcsec"));
    meet += v.back() <= req ? 1 : 0;
  }
  std::sort(v.begin(), v.end());
  const double median = 0.5 * (v[149] + v[150]);
  EXPECT_NEAR(s["outputs"]["los_max_arcsec"]["p50"]["value"].get<double>(), median, 1e-6);
  EXPECT_NEAR(s["outputs"]["los_max_arcsec"]["max"]["value"].get<double>(), v.back(), 1e-6);
  EXPECT_NEAR(s["details"]["fraction_samples_meeting"]["value"].get<double>(), static_cast<double>(meet) / 300.0, 1e-12);
  EXPECT_NEAR(req, 18.75, 1e-9);  // 1 px at the model's IFOV
  // 3. No budget is built into the seeker kind: the paper's budget is a budget file
  //    (studies/wang2011_budget.toml), checked term by term in budget_test.
  EXPECT_FALSE(s.contains("budget"));
  // 4. Provenance and sweeps present.
  EXPECT_EQ(s["provenance"]["samples"], 300);
  EXPECT_EQ(s["provenance"]["study_file_sha1"].get<std::string>().size(), 40u);
  ASSERT_EQ(s["sweeps"].size(), 1u);
  const auto& pts = s["sweeps"][0]["points"];
  // A longer yaw span lowers the LOS error (same random numbers at both values).
  EXPECT_GT(pts[0]["outputs"]["los_max_arcsec"]["p95"]["value"].get<double>(),
            pts[1]["outputs"]["los_max_arcsec"]["p95"]["value"].get<double>());
  EXPECT_TRUE(std::filesystem::exists(d.file("run/report.html")));
}

TEST(StudyRunner, SweepsAndContributionsDoNotDependOnTheThreadCount) {
  // They run side by side on the run's threads, one thread each: the figures must not care.
  TempDir d;
  std::string text = test::read_text(small_study(d));
  text += "\n[output]\ncontribution_samples = 64\n";
  const std::string study = d.file("study_contributions.toml");
  test::write_text(study, text);
  run_study(study, options(d.file("t1"), 1));
  run_study(study, options(d.file("t3"), 3));
  const json a = json::parse(test::read_text(d.file("t1/summary.json")));
  const json b = json::parse(test::read_text(d.file("t3/summary.json")));
  ASSERT_EQ(a["sweeps"][0]["points"].size(), 2u);
  ASSERT_GT(a["contributions"].size(), 2u);
  EXPECT_EQ(a["sweeps"], b["sweeps"]);
  EXPECT_EQ(a["contributions"], b["contributions"]);
}

TEST(StudyRunner, NeverOverwritesARun) {
  TempDir d;
  const std::string study = small_study(d);
  RunOptions o = options("", 1);
  o.results_root = d.file("results");
  const std::string a = run_study(study, o);
  const std::string b = run_study(study, o);
  EXPECT_NE(a, b);
  EXPECT_TRUE(std::filesystem::exists(a + "/samples.csv"));
  EXPECT_TRUE(std::filesystem::exists(b + "/samples.csv"));
  try {
    run_study(study, options(a, 1));
    FAIL() << "overwrote " << a;
  } catch (const UsageError& e) {  // refused input: exit status 2
    EXPECT_NE(std::string(e.what()).find("already holds a run"), std::string::npos) << e.what();
  }
}

TEST(StudyRunner, InvalidStudyRunsNothing) {
  TempDir d;
  std::string text = test::read_text(small_study(d));
  text = test::replace_once(text, "los_error = \"1 px\"", "los_error = \"1\"");
  test::write_text(d.file("bad.toml"), text);
  EXPECT_THROW(run_study(d.file("bad.toml"), options(d.file("out"), 1)), ValidationError);
  EXPECT_FALSE(std::filesystem::exists(d.file("out/samples.csv")));
}

}  // namespace
}  // namespace poise::engine

namespace poise::engine {
namespace {

// The figures quoted in the default study's notes and in the issue note come from this run;
// if the engine changes them, the notes must be revised.
TEST(StudyRunner, DefaultStudyFiguresQuotedInItsNotes) {
  TempDir d;
  RunOptions o = options(d.file("run"), 2);
  run_study(test::source_path("studies/los_seeker_wang2011.toml"), o);
  const json s = json::parse(test::read_text(d.file("run/summary.json")));
  const auto& lm = s["outputs"]["los_max_arcsec"];
  EXPECT_NEAR(lm["p50"]["value"].get<double>(), 16.9, 0.05);
  EXPECT_NEAR(lm["p95"]["value"].get<double>(), 31.2, 0.05);
  EXPECT_NEAR(lm["p99_73"]["value"].get<double>(), 43.1, 0.05);
  EXPECT_NEAR(s["details"]["fraction_samples_meeting"]["value"].get<double>(), 0.60, 0.005);
  EXPECT_NEAR(s["details"]["fraction_field_meeting"]["value"].get<double>(), 0.86, 0.005);
  EXPECT_EQ(s["failures"]["count"], 0);
}

}  // namespace
}  // namespace poise::engine
