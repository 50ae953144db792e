// Tests of issue 9's reliability and scale features: randomized replicates and the Saltelli
// layout of the designs, replicate intervals, the stop rule (--until, failure share), atomic
// writes, and end to end through the poise binary: SIGINT/SIGTERM/kill -9 then --resume to
// exactly an uninterrupted run's results, --until, too many failures, sensitivity indices,
// and 2 MPI ranks giving a one-process run's samples and statistics.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "sampling/design.h"
#include "sampling/random_stream.h"
#include "sampling/statistics.h"
#include "engine/run/convergence.h"
#include "engine/results/result_io.h"
#include "h5_util.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
namespace ps = poise::sampling;
using nlohmann::json;
using poise::test::TempDir;

// ---- designs -------------------------------------------------------------------------

std::vector<double> design_points(const ps::Design& d, std::size_t from, std::size_t to) {
  std::vector<double> out((to - from) * d.dimension());
  for (std::size_t i = from; i < to; ++i) d.point(i, std::span<double>(out.data() + (i - from) * d.dimension(), d.dimension()));
  return out;
}

TEST(Replicates, EachReplicateIsAStratifiedDesignOfItsOwn) {
  const std::size_t m = 256, dim = 6, reps = 4;
  for (auto method : {ps::SamplingMethod::kSobol, ps::SamplingMethod::kLatinHypercube}) {
    SCOPED_TRACE(ps::to_string(method));
    ps::DesignOptions o;
    o.replicate_size = m;
    const ps::Design d(method, 99, m * reps, dim, o);
    std::vector<std::vector<double>> all;
    for (std::size_t r = 0; r < reps; ++r) {
      const std::vector<double> p = design_points(d, r * m, (r + 1) * m);
      // One point in each of the m strata of every dimension (a Latin hypercube; for a
      // scrambled Sobol 2^8-point net, its one-dimensional projections are too).
      for (std::size_t k = 0; k < dim; ++k) {
        std::set<std::size_t> strata;
        for (std::size_t j = 0; j < m; ++j) strata.insert(static_cast<std::size_t>(p[j * dim + k] * m));
        EXPECT_EQ(strata.size(), m) << "replicate " << r << " dimension " << k;
      }
      all.push_back(p);
    }
    // Replicates differ, and a point is the same however it is reached (order, copies).
    EXPECT_NE(all[0], all[1]);
    const ps::Design copy = d;
    EXPECT_EQ(design_points(copy, 2 * m, 3 * m), all[2]);
    EXPECT_EQ(design_points(d, 3 * m, 4 * m), all[3]);
  }
}

TEST(Replicates, ScrambledSobolHasTheTwoDimensionalNetProperty) {
  // A (0, m, 2) net in base 2 for dimensions 1 and 2 of a Sobol sequence: every elementary
  // box of area 1/m holds exactly one point; linear scrambling and digital shift keep it.
  const std::size_t m = 64;
  ps::DesignOptions o;
  o.replicate_size = m;
  const ps::Design d(ps::SamplingMethod::kSobol, 5, 3 * m, 2, o);
  const std::vector<double> p = design_points(d, m, 2 * m);  // replicate 1
  for (std::size_t bx = 1; bx < m; bx *= 2) {
    const std::size_t by = m / bx;
    std::set<std::pair<std::size_t, std::size_t>> boxes;
    for (std::size_t j = 0; j < m; ++j) {
      boxes.insert({static_cast<std::size_t>(p[2 * j] * static_cast<double>(bx)), static_cast<std::size_t>(p[2 * j + 1] * static_cast<double>(by))});
    }
    EXPECT_EQ(boxes.size(), m) << bx << " x " << by;
  }
}

TEST(Replicates, ReplicateIntervalsCoverTheTruth) {
  // The mean of U(0,1)^2 summed over 3 dimensions (exactly 1), from 8 LHS replicates of 64:
  // the replicate t-intervals must cover the exact mean (1) in about 95% of repetitions.
  const std::size_t m = 64, reps = 8, dim = 3;
  int covered = 0;
  const int trials = 60;
  for (int t = 0; t < trials; ++t) {
    ps::DesignOptions o;
    o.replicate_size = m;
    const ps::Design d(ps::SamplingMethod::kLatinHypercube, 1000 + t, m * reps, dim, o);
    std::vector<double> v(m * reps);
    std::vector<std::size_t> rep(m * reps);
    std::vector<double> u(dim);
    for (std::size_t i = 0; i < v.size(); ++i) {
      d.point(i, u);
      v[i] = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
      rep[i] = i / m;
    }
    const ps::Summary s = ps::summarize_replicates(v, rep);
    ASSERT_TRUE(s.mean.lo && s.mean.hi);
    covered += (*s.mean.lo <= 1.0 && 1.0 <= *s.mean.hi) ? 1 : 0;
    // LHS reduces the variance of the mean: the replicate interval is narrower than the
    // independent-samples one.
    EXPECT_LT(*s.mean.hi - *s.mean.lo, *ps::summarize(v).mean.hi - *ps::summarize(v).mean.lo);
  }
  EXPECT_GE(covered, 52) << covered << " of " << trials;
}

TEST(Saltelli, LayoutTakesEachGroupFromB) {
  const std::size_t n = 16, dim = 3;
  ps::DesignOptions o;
  o.saltelli_base = n;
  o.saltelli_noise_group = true;
  const ps::Design d(ps::SamplingMethod::kSobol, 3, n * (dim + 1 + 2), dim, o);
  EXPECT_EQ(d.saltelli_groups(), dim + 1);
  std::vector<double> a(dim), b(dim), ab(dim);
  for (std::size_t j = 0; j < n; ++j) {
    d.point(j, a);
    d.point(n + j, b);
    for (std::size_t k = 0; k < dim; ++k) EXPECT_NE(a[k], b[k]);
    for (std::size_t g = 0; g <= dim; ++g) {
      d.point((2 + g) * n + j, ab);
      for (std::size_t k = 0; k < dim; ++k) EXPECT_EQ(ab[k], k == g ? b[k] : a[k]) << "row " << j << " group " << g;
      // The noise group (g = dim) keys its own randomness like B; the others like A.
      EXPECT_EQ(d.stream_index((2 + g) * n + j), g == dim ? d.stream_index(n + j) : d.stream_index(j));
    }
    EXPECT_NE(d.stream_index(j), d.stream_index(n + j));
  }
  EXPECT_THROW(ps::Design(ps::SamplingMethod::kSobol, 3, 10, dim, o), poise::Error);
}

TEST(Saltelli, EachSourceOfTheWithinSampleRandomnessHasItsOwnGroup) {
  // Two sources (per-test draws, measurement noise): group dim + s keys source s like B and
  // the other source like A; A's and B's rows key both like themselves; the point of a
  // source's row is A's.
  const std::size_t n = 8, dim = 2, sources = 2;
  ps::DesignOptions o;
  o.saltelli_base = n;
  o.saltelli_noise_group = true;
  o.saltelli_noise_sources = sources;
  const ps::Design d(ps::SamplingMethod::kSobol, 5, n * (dim + sources + 2), dim, o);
  EXPECT_EQ(d.saltelli_groups(), dim + sources);
  std::vector<double> a(dim), ab(dim);
  for (std::size_t j = 0; j < n; ++j) {
    d.point(j, a);
    for (std::size_t s = 0; s < sources; ++s) {
      EXPECT_EQ(d.stream_index(j, s), d.stream_index(j, 0));
      EXPECT_EQ(d.stream_index(n + j, s), d.stream_index(n + j, 0));
      EXPECT_NE(d.stream_index(j, s), d.stream_index(n + j, s));
      for (std::size_t g = 0; g < sources; ++g) {
        const std::size_t i = (2 + dim + g) * n + j;
        d.point(i, ab);
        for (std::size_t k = 0; k < dim; ++k) EXPECT_EQ(ab[k], a[k]);
        EXPECT_EQ(d.stream_index(i, s), s == g ? d.stream_index(n + j, s) : d.stream_index(j, s)) << g << " " << s;
      }
    }
  }
}

TEST(Sensitivity, BalancingMachineSplitsItsRandomnessBySource) {
  // The balancing machine draws its per-test tolerances and its sensors' noise from two
  // streams: two Sobol groups instead of one "within-sample randomness".
  TempDir d;
  std::string text = poise::test::read_text(poise::test::source_path("studies/wang2014_balancing_mc.toml"));
  text = poise::test::replace_once(text, "model = \"../models/", "model = \"" + poise::test::source_path("models") + "/");
  poise::test::write_text(d.file("b.toml"), text);
  auto r = poise::test::run_poise(d, "sensitivity '" + d.file("b.toml") + "' --base 4 -q --no-plots --out '" +
                                         d.file("s") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const json s = json::parse(poise::test::read_text(d.file("s/summary.json")));
  const json& groups = s["sensitivity"]["groups"];
  int sources = 0;
  for (const json& g : groups) {
    sources += g == "(within-sample randomness: per-test draws)" || g == "(within-sample randomness: measurement noise)";
  }
  EXPECT_EQ(sources, 2) << groups.dump();
  std::size_t closed = 0;
  for (const json& t : s["sensitivity"]["outputs"].begin().value()["tolerances"]) closed += t["columns"].get<std::size_t>() > 1;
  EXPECT_EQ(s["sampling"]["samples"].get<std::size_t>(), 4 * (groups.size() + closed + 2));
}

// ---- stop rule, atomic writes --------------------------------------------------------

TEST(StopRule, UntilTargetsAreParsedStrictly) {
  const std::vector<std::string> outs = {"los_max_arcsec", "g_rmse_torque_mNm"};
  const auto t = poise::engine::parse_until("los_max_arcsec.p99_73<=0.5", outs);
  EXPECT_EQ(t.output, "los_max_arcsec");
  EXPECT_EQ(t.statistic, "p99_73");
  EXPECT_DOUBLE_EQ(t.width, 0.5);
  EXPECT_FALSE(t.relative);
  const auto r = poise::engine::parse_until("g_rmse_torque_mNm.mean<=2%", outs);
  EXPECT_TRUE(r.relative);
  EXPECT_DOUBLE_EQ(r.width, 0.02);
  for (const char* bad : {"los_max_arcsec.p99_73", "nope.p95<=1", "los_max_arcsec.p97<=1", "los_max_arcsec.p95<=x",
                          "los_max_arcsec.p95<=-1"}) {
    EXPECT_THROW(poise::engine::parse_until(bad, outs), poise::Error) << bad;
  }
}

TEST(StopRule, StopsOnTooManyFailuresAndAtTheTargetWidth) {
  using poise::engine::StopRule;
  // 10% failing against a 5% limit: stopped once the failure share is clearly above it.
  StopRule f({"x"}, 10000, 0.05, std::nullopt, 0, false);
  std::vector<std::vector<double>> v(1);
  std::vector<std::size_t> ok;
  std::string why;
  std::size_t i = 0;
  for (; i < 10000 && why.empty(); ++i) {
    if (i % 10 != 9) {
      v[0].push_back(1.0);
      ok.push_back(i);
    }
    why = f(v, ok, (i + 1) / 10, i + 1);
  }
  EXPECT_TRUE(f.failed());
  EXPECT_NE(why.find("max_failure_share"), std::string::npos) << why;
  EXPECT_LT(i, 2000u);  // well before the end
  // 1% failing: never stopped.
  StopRule g({"x"}, 1000, 0.05, std::nullopt, 0, false);
  for (std::size_t k = 1; k <= 1000; ++k) EXPECT_EQ(g({{}}, {}, k / 100, k), "");

  // Normal(0,1) mean to a 0.1-wide interval: needs about (2 * 1.96 / 0.1)^2 = 1537 samples.
  StopRule u({"x"}, 100000, 0.05, poise::engine::parse_until("x.mean<=0.1", {"x"}), 0, false);
  std::vector<std::vector<double>> w(1);
  std::vector<std::size_t> idx;
  std::size_t n = 0;
  for (why.clear(); why.empty() && n < 100000; ++n) {
    ps::RandomStream rs(1, ps::StreamId::kNoise, n);
    const double z = std::sqrt(-2.0 * std::log(rs.uniform())) * std::cos(2.0 * M_PI * rs.uniform());
    w[0].push_back(z);
    idx.push_back(n);
    why = u(w, idx, 0, n + 1);
  }
  EXPECT_FALSE(u.failed());
  EXPECT_NE(why.find("until"), std::string::npos);
  EXPECT_GT(n, 1300u);
  EXPECT_LT(n, 1900u);
  EXPECT_TRUE(u.until_json()["met"].get<bool>());
}

TEST(AtomicWrite, ReplacesWholeAndLeavesNoTemporary) {
  TempDir d;
  const std::string p = d.file("summary.json");
  poise::engine::write_file_atomic(p, "old\n");
  poise::engine::write_file_atomic(p, "{\"new\": 1}\n");
  EXPECT_EQ(poise::test::read_text(p), "{\"new\": 1}\n");
  EXPECT_FALSE(fs::exists(p + ".tmp"));
  EXPECT_THROW(poise::engine::write_file_atomic(d.file("no/such/dir/x.json"), "x"), poise::Error);
}

TEST(CsvNumbers, ReadBackExactly) {
  for (double v : {0.1, 1.0 / 3.0, 43.28028319560695, -2.5e-300, 1e300, 123456789.123456789}) {
    EXPECT_EQ(std::stod(poise::engine::csv_number(v)), v);
  }
  EXPECT_EQ(poise::engine::csv_number(NAN), "nan");
}

// ---- end to end through the binary ---------------------------------------------------

// Starts `poise args` in the background (stdout/stderr to files in dir); returns its pid. With
// `hold_at` the run holds before that sample until a signal (POISE_INJECT_HOLD_AT_SAMPLE,
// engine/results/fault_injection.h): it cannot end before the test has signalled it.
pid_t start_poise(const TempDir& dir, const std::string& args, std::size_t hold_at) {
  const std::string cmd = "POISE_INJECT_HOLD_AT_SAMPLE=" + std::to_string(hold_at) + " exec '" + ::poise::test::poise_binary() +
                          "' " + args + " >'" + dir.file("bg_out.txt") + "' 2>'" + dir.file("bg_err.txt") + "'";
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

std::size_t lines_of(const std::string& path) {
  const std::string t = poise::test::read_text(path);
  return static_cast<std::size_t>(std::count(t.begin(), t.end(), '\n'));
}

// Waits until the held run of start_poise has reached its held sample (the hook's line on
// stderr) and `path` has at least `lines` lines; false if the process ended first. A held run
// cannot end by itself, so this waits on the run's progress, not on the machine's speed.
bool wait_until_held(pid_t pid, const TempDir& dir, const std::string& path, std::size_t lines) {
  for (;;) {
    if (poise::test::read_text(dir.file("bg_err.txt")).find("held until SIGINT") != std::string::npos &&
        lines_of(path) >= lines) {
      return true;
    }
    int st = 0;
    if (waitpid(pid, &st, WNOHANG) == pid) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

int wait_exit(pid_t pid) {
  int st = 0;
  waitpid(pid, &st, 0);
  if (WIFEXITED(st)) return WEXITSTATUS(st);
  if (WIFSIGNALED(st)) return 128 + WTERMSIG(st);
  return -1;
}

// summary.json without what may differ between equal runs (time, threads, ranks, resume).
// CI runs as root in a container: Open MPI refuses root unless told (the flag, and its
// environment form for the ranks' own checks).
[[maybe_unused]] constexpr const char* kMpiRootEnv = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ";

json comparable(const std::string& dir) {
  json s = json::parse(poise::test::read_text(dir + "/summary.json"));
  s.erase("provenance");
  s["sampling"].erase("threads");
  s["sampling"].erase("mpi_ranks");
  if (s.contains("solver")) s.erase("solver");
  return s;
}

std::string seeker_study(const TempDir& d, const std::string& sampling_extra = "", const std::string& overrides = "") {
  std::string text = poise::test::read_text(poise::test::source_path("studies/los_seeker_wang2011.toml"));
  text = poise::test::replace_once(text, "model = \"../models/", "model = \"" + poise::test::source_path("models") + "/");
  text = poise::test::replace_once(text, "[sampling]\n", "[sampling]\n" + sampling_extra);
  // Sweeps and contributions are not under test here: keep the runs short.
  const auto sweep = text.find("[[sweep]]");
  if (sweep != std::string::npos) text.resize(sweep);
  text += "\n[output]\ncontribution_samples = 0\nplots = false\n" + overrides;
  const std::string p = d.file("seeker.toml");
  poise::test::write_text(p, text);
  return p;
}

TEST(Interrupt, SigintStopsCleanlyAndResumeGivesTheUninterruptedResult) {
  TempDir d;
  const std::string study = seeker_study(d);
  const std::string args = "run '" + study + "' --samples 40000 --threads 2 -q --no-plots --out ";
  // Held at sample 2048: the two chunks of 1024 before it are written, the run waits for the signal.
  const pid_t pid = start_poise(d, args + "'" + d.file("cut") + "'", 2048);
  ASSERT_TRUE(wait_until_held(pid, d, d.file("cut/samples.csv"), 2049)) << poise::test::read_text(d.file("bg_err.txt"));
  kill(pid, SIGINT);
  EXPECT_EQ(wait_exit(pid), 130);
  const std::string err = poise::test::read_text(d.file("bg_err.txt"));
  EXPECT_NE(err.find("SIGINT: stopped after"), std::string::npos) << err;
  EXPECT_NE(err.find("--resume"), std::string::npos) << err;
  const json cut = json::parse(poise::test::read_text(d.file("cut/summary.json")));
  EXPECT_EQ(cut["status"], "interrupted");
  const std::size_t ran = cut["sampling"]["samples"].get<std::size_t>();
  EXPECT_LT(ran, 40000u);
  EXPECT_EQ(lines_of(d.file("cut/samples.csv")), ran + 1);

  auto r = poise::test::run_poise(d, "run '" + study + "' -q --no-plots --resume '" + d.file("cut") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  r = poise::test::run_poise(d, args + "'" + d.file("whole") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(poise::test::read_text(d.file("cut/samples.csv")), poise::test::read_text(d.file("whole/samples.csv")));
  EXPECT_EQ(comparable(d.file("cut")), comparable(d.file("whole")));
  // samples.h5: the grid values of the resumed run are those of the uninterrupted one.
  EXPECT_TRUE(poise::test::same_h5_floats(poise::test::read_h5_floats(d.file("cut/samples.h5"), "grid_total_arcsec"),
                                          poise::test::read_h5_floats(d.file("whole/samples.h5"), "grid_total_arcsec")));
}

TEST(Interrupt, KillNineKeepsFinishedSamplesOfAProcedureStudy) {
  // The gimbal test simulated end to end: killed hard mid-run, its samples.csv keeps every
  // finished row (a partial last line is cut on resume) and --resume completes it exactly.
  TempDir d;
  const std::string study = poise::test::source_path("studies/gimbal_unbalance_mc.toml");
  const std::string args = "run '" + study + "' --samples 64 --threads 2 -q --no-plots --out ";
  const pid_t pid = start_poise(d, args + "'" + d.file("cut") + "'", 32);  // chunks of 8: 32 rows written
  ASSERT_TRUE(wait_until_held(pid, d, d.file("cut/samples.csv"), 20)) << poise::test::read_text(d.file("bg_err.txt"));
  kill(pid, SIGKILL);
  EXPECT_EQ(wait_exit(pid), 128 + SIGKILL);
  EXPECT_FALSE(fs::exists(d.file("cut/summary.json")));
  auto r = poise::test::run_poise(d, "run '" + study + "' -q --no-plots --resume '" + d.file("cut") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  r = poise::test::run_poise(d, args + "'" + d.file("whole") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(poise::test::read_text(d.file("cut/samples.csv")), poise::test::read_text(d.file("whole/samples.csv")));
  EXPECT_EQ(comparable(d.file("cut")), comparable(d.file("whole")));
  EXPECT_EQ(json::parse(poise::test::read_text(d.file("cut/run.json")))["status"], "complete");
  // Killed before it could record its counters: the summary says which part they leave out.
  const json solver = json::parse(poise::test::read_text(d.file("cut/summary.json")))["solver"];
  ASSERT_TRUE(solver.contains("rhs_evals_note")) << solver.dump(2);
  EXPECT_NE(solver["rhs_evals_note"].get<std::string>().find("leaves out"), std::string::npos);
}

TEST(Interrupt, ResumedBalancingRunCountsTheSolverWorkOfBothParts) {
  // samples.csv holds each sample's solver steps but not its right-hand-side evaluations:
  // the interrupted part records them in run.json, so the resumed summary's solver counters
  // equal an uninterrupted run's.
  TempDir d;
  const std::string study = poise::test::source_path("studies/wang2014_balancing_mc.toml");
  const std::string args = "run '" + study + "' --samples 64 --threads 2 -q --no-plots --out ";
  const pid_t pid = start_poise(d, args + "'" + d.file("cut") + "'", 16);  // chunks of 8: 16 rows written
  ASSERT_TRUE(wait_until_held(pid, d, d.file("cut/samples.csv"), 9)) << poise::test::read_text(d.file("bg_err.txt"));
  kill(pid, SIGINT);
  ASSERT_EQ(wait_exit(pid), 130) << poise::test::read_text(d.file("bg_err.txt"));
  const json first = json::parse(poise::test::read_text(d.file("cut/run.json")));
  ASSERT_TRUE(first.contains("solver_counters")) << first.dump(2);
  const std::size_t ran = first["solver_counters"]["samples"].get<std::size_t>();
  EXPECT_GT(ran, 0u);
  EXPECT_LT(ran, 64u);
  EXPECT_GT(first["solver_counters"]["rhs_evals"].get<long>(), 0);
  auto r = poise::test::run_poise(d, "run '" + study + "' -q --no-plots --resume '" + d.file("cut") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  r = poise::test::run_poise(d, args + "'" + d.file("whole") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const json cut = json::parse(poise::test::read_text(d.file("cut/summary.json")))["solver"];
  const json whole = json::parse(poise::test::read_text(d.file("whole/summary.json")))["solver"];
  EXPECT_GT(whole["rhs_evals"].get<long>(), 0);
  EXPECT_EQ(cut["rhs_evals"], whole["rhs_evals"]);
  EXPECT_EQ(cut["steps"], whole["steps"]);
  EXPECT_FALSE(cut.contains("rhs_evals_note")) << cut.dump(2);
  EXPECT_EQ(poise::test::read_text(d.file("cut/samples.csv")), poise::test::read_text(d.file("whole/samples.csv")));
}

TEST(Until, StopsAtTheSameReplicateForAnyThreadCount) {
  TempDir d;
  const std::string study = seeker_study(d, "replicate_size = 512\n");
  const std::string args = "run '" + study + "' --until 'los_max_arcsec.p95<=1.5' --max-samples 65536 -q --no-plots";
  auto r1 = poise::test::run_poise(d, args + " --threads 1 --out '" + d.file("t1") + "'");
  ASSERT_EQ(r1.status, 0) << r1.err;
  auto r2 = poise::test::run_poise(d, args + " --threads 2 --out '" + d.file("t2") + "'");
  ASSERT_EQ(r2.status, 0) << r2.err;
  const json s = comparable(d.file("t1"));
  EXPECT_EQ(s, comparable(d.file("t2")));
#if defined(POISE_MPIEXEC) && defined(POISE_BUILT_WITH_MPI)
  // Two ranks, rank 0 taking a share of each round that changes with its timing: the stop rule
  // sees the same chunks in the same order, and stops at the same sample.
  const std::string mpi = kMpiRootEnv + std::string("'") + POISE_MPIEXEC + "' --allow-run-as-root --oversubscribe -np 2 '" +
                          ::poise::test::poise_binary() + "' " + args + " --threads 1 --out '" + d.file("r2") + "' >'" +
                          d.file("mpi_until.txt") + "' 2>&1";
  const int raw = std::system(mpi.c_str());
  ASSERT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) == 0) << poise::test::read_text(d.file("mpi_until.txt"));
  EXPECT_EQ(s, comparable(d.file("r2")));
  EXPECT_EQ(poise::test::read_text(d.file("t1/samples.csv")), poise::test::read_text(d.file("r2/samples.csv")));
#endif
  const json& u = s["sample_convergence"]["until"];
  ASSERT_TRUE(u["met"].get<bool>()) << u.dump();
  const std::size_t n = u["met_at_samples"].get<std::size_t>();
  EXPECT_EQ(n % 512, 0u);
  EXPECT_EQ(s["sampling"]["samples"].get<std::size_t>(), n);
  EXPECT_LT(n, 65536u);
  const json& p95 = s["outputs"]["los_max_arcsec"]["p95"];
  EXPECT_LE(p95["ci95"][1].get<double>() - p95["ci95"][0].get<double>(), 1.5);
  // Without replicates a Sobol design cannot grow: refused, with the reason.
  auto bad = poise::test::run_poise(d, "run '" + poise::test::source_path("studies/los_seeker_wang2011.toml") +
                                           "' --until 'los_max_arcsec.p95<=1' -q --out '" + d.file("bad") + "'");
  EXPECT_EQ(bad.status, 2);  // refused input, and nothing on disk
  EXPECT_NE(bad.err.find("replicate_size"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(d.file("bad")));
}

TEST(Failures, RecordedWithTheirSeedAndTooManyStopTheRun) {
  TempDir d;
  const std::string study = seeker_study(d);
  // Every 50th sample fails: 2% is within the default 5%; each is recorded.
  setenv("POISE_INJECT_FAILURE_EVERY", "50", 1);
  auto r = poise::test::run_poise(d, "run '" + study + "' --samples 2000 --seed 9 -q --no-plots --out '" + d.file("ok") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const json s = json::parse(poise::test::read_text(d.file("ok/summary.json")));
  EXPECT_EQ(s["failures"]["count"], 40);
  EXPECT_EQ(s["outputs"]["los_max_arcsec"]["n"], 1960);
  const json& first = s["failures"]["first"][0];
  EXPECT_EQ(first["sample"], 49);
  EXPECT_EQ(first["seed"], 9);
  EXPECT_NE(first["replay"].get<std::string>().find("--sample 49 --seed 9"), std::string::npos);
  const std::string csv = poise::test::read_text(d.file("ok/samples.csv"));
  EXPECT_NE(csv.find("\n49,failed,"), std::string::npos);
  // Every 10th fails: more than 5%, the run stops early with a clear error, keeping its rows.
  setenv("POISE_INJECT_FAILURE_EVERY", "10", 1);
  r = poise::test::run_poise(d, "run '" + study + "' --samples 200000 -q --no-plots --out '" + d.file("bad") + "'");
  unsetenv("POISE_INJECT_FAILURE_EVERY");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("max_failure_share"), std::string::npos) << r.err;
  const json b = json::parse(poise::test::read_text(d.file("bad/summary.json")));
  EXPECT_EQ(b["status"], "failed");
  EXPECT_LT(b["sampling"]["samples"].get<std::size_t>(), 200000u);
  EXPECT_EQ(lines_of(d.file("bad/samples.csv")), b["sampling"]["samples"].get<std::size_t>() + 1);
}

TEST(Sensitivity, TheDominantToleranceDrivesTheLosError) {
  // Pitch perpendicularity made 20x its drawing value: it must carry most of the variance of
  // the greatest LOS error, and a tolerance that is switched off none of it.
  TempDir d;
  const std::string study = seeker_study(d, "", "\n[overrides]\n\"pitch.perpendicularity.tolerance\" = \"0.08 mm\"\n"
                                                "\"yaw.radial_runout.tolerance\" = \"0 mm\"\n");
  auto r = poise::test::run_poise(d, "sensitivity '" + study + "' --base 512 -q --no-plots --out '" + d.file("s") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const json s = json::parse(poise::test::read_text(d.file("s/summary.json")));
  const json& sens = s["sensitivity"];
  const std::size_t groups = sens["groups"].size();
  const json& los = sens["outputs"]["los_max_arcsec"];
  // Per column, plus one closed group per tolerance drawn in several columns (issue 21).
  std::size_t closed = 0;
  for (const auto& t : los["tolerances"]) closed += t["columns"].get<std::size_t>() > 1 ? 1 : 0;
  EXPECT_EQ(closed, 13u);  // yaw perpendicularity (tilt, azimuth) and 6 bearing sources per axis
  EXPECT_EQ(s["sampling"]["samples"].get<std::size_t>(), 512 * (groups + closed + 2));
  EXPECT_EQ(los["tolerances"][0]["group"], "pitch.perpendicularity") << los["tolerances"].dump();
  for (const auto& t : los["tolerances"]) {
    if (t["group"] == "yaw.radial_runout") {
      EXPECT_EQ(t["total"]["value"].get<double>(), 0.0) << t.dump();
    }
  }
  const json& top = los["indices"][0];
  EXPECT_EQ(top["group"], "pitch_perpendicularity_arcsec") << los.dump();
  EXPECT_GT(top["total"]["value"].get<double>(), 0.7);
  EXPECT_GT(top["first"]["value"].get<double>(), 0.5);
  for (const auto& g : los["indices"]) {
    if (g["group"].get<std::string>().rfind("yaw_radial_runout", 0) == 0) {
      EXPECT_EQ(g["total"]["value"].get<double>(), 0.0) << g.dump();
    }
  }
  EXPECT_NE(poise::test::read_text(d.file("s/report.html")).find("Sobol indices"), std::string::npos);
}

TEST(Sensitivity, GeometryStudyThicknessDrivesTheDiskMass) {
  // Any study kind: the simulator disk as built (coarse ray grid, few base rows). Its mass and
  // polar inertia follow the thickness tolerance; a hole position barely matters.
  TempDir d;
  std::string text = poise::test::read_text(poise::test::source_path("studies/geometry_mass_properties.toml"));
  text = poise::test::replace_once(text, "model = \"../models/", "model = \"" + poise::test::source_path("models") + "/");
  text = poise::test::replace_once(text, "rays_per_side = 200", "rays_per_side = 16");
  text = poise::test::replace_once(text, "convergence = [25, 50, 100, 200, 400]", "convergence = [8]");
  text = poise::test::replace_once(text, "export_mesh = true", "export_mesh = false");
  poise::test::write_text(d.file("disk.toml"), text);
  auto r = poise::test::run_poise(d, "sensitivity '" + d.file("disk.toml") + "' --base 16 -q --no-plots --out '" +
                                         d.file("s") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const json s = json::parse(poise::test::read_text(d.file("s/summary.json")));
  EXPECT_EQ(s["status"], "complete");
  const std::size_t groups = s["sensitivity"]["groups"].size();
  EXPECT_EQ(s["sampling"]["samples"].get<std::size_t>(), 16 * (groups + 2));
  for (const char* out : {"mass_g", "Jzz_kgm2"}) {
    const json& top = s["sensitivity"]["outputs"][out]["indices"][0];
    EXPECT_EQ(top["group"], "thickness_dev_mm") << out;
    EXPECT_GT(top["total"]["value"].get<double>(), 0.9) << out;
  }
}

TEST(Sensitivity, ProcedureStudyGroupsATolerancesColumnsTogether) {
  // A procedure kind: the gimbal's residual unbalance is drawn as a magnitude and an angle
  // (two design dimensions); its Sobol group is the model key with both columns closed
  // together, beside the per-column detail, and the layout has one more block per group.
  TempDir d;
  std::string text = poise::test::read_text(poise::test::source_path("studies/gimbal_unbalance_mc.toml"));
  text = poise::test::replace_once(text, "model = \"../models/", "model = \"" + poise::test::source_path("models") + "/");
  poise::test::write_text(d.file("g.toml"), text);
  auto r = poise::test::run_poise(d, "sensitivity '" + d.file("g.toml") + "' --base 4 -q --no-plots --out '" +
                                         d.file("s") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const json s = json::parse(poise::test::read_text(d.file("s/summary.json")));
  const json& sens = s["sensitivity"];
  const json& out = sens["outputs"].begin().value();
  std::size_t closed = 0;
  bool residual = false;
  for (const json& t : out["tolerances"]) {
    closed += t["columns"].get<std::size_t>() > 1;
    if (t["group"] == "tolerances.residual_unbalance") {
      residual = true;
      EXPECT_EQ(t["columns"], 2) << t.dump();
    }
  }
  EXPECT_TRUE(residual) << out["tolerances"].dump();
  EXPECT_GE(closed, 2u);  // residual unbalance, run-out, axis tilt: magnitude and angle each
  EXPECT_EQ(sens["evaluations"].get<std::size_t>(), 4 * (sens["groups"].size() + closed + 2));
  EXPECT_EQ(s["sampling"]["samples"].get<std::size_t>(), sens["evaluations"].get<std::size_t>());
  bool per_column = false;
  for (const json& g : out["indices"]) per_column = per_column || g["group"] == "residual_unbalance_angle_deg";
  EXPECT_TRUE(per_column) << out["indices"].dump();
}


TEST(Mpi, TwoRanksGiveTheSamplesAndStatisticsOfOneProcess) {
#if !defined(POISE_MPIEXEC)
  GTEST_SKIP() << "mpirun is not installed (scripts/install_deps.sh installs openmpi-bin and libopenmpi-dev)";
#elif !defined(POISE_BUILT_WITH_MPI)
  FAIL() << "mpirun (" << POISE_MPIEXEC << ") is installed but poise was built without MPI: install "
         << "libopenmpi-dev (scripts/install_deps.sh) and configure with POISE_WITH_MPI=ON";
#else
  TempDir d;
  const std::string study = seeker_study(d);
  // 20 chunks of 1024: a first round of even shares, then rounds where rank 0, which writes,
  // takes the share that balances its work (engine/run/sample_driver.h).
  const std::string args = "run '" + study + "' --samples 20000 -q --no-plots";
  auto one = poise::test::run_poise(d, args + " --out '" + d.file("one") + "'");
  ASSERT_EQ(one.status, 0) << one.err;
  const std::string mpi = kMpiRootEnv + std::string("'") + POISE_MPIEXEC + "' --allow-run-as-root --oversubscribe -np 2 '" +
                          ::poise::test::poise_binary() + "' " + args + " --threads 1 --out '" + d.file("two") + "' >'" +
                          d.file("mpi_out.txt") + "' 2>&1";
  const int raw = std::system(mpi.c_str());
  ASSERT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) == 0) << poise::test::read_text(d.file("mpi_out.txt"));
  EXPECT_EQ(poise::test::read_text(d.file("one/samples.csv")), poise::test::read_text(d.file("two/samples.csv")));
  EXPECT_EQ(comparable(d.file("one")), comparable(d.file("two")));
  EXPECT_TRUE(poise::test::same_h5_floats(poise::test::read_h5_floats(d.file("one/samples.h5"), "grid_total_arcsec"),
                                          poise::test::read_h5_floats(d.file("two/samples.h5"), "grid_total_arcsec")));
  const json p = json::parse(poise::test::read_text(d.file("two/summary.json")))["provenance"];
  EXPECT_EQ(p["mpi_ranks"], 2);
  // A procedure study too (rank 0 also gathers the other rank's simulated tests).
  const std::string g = poise::test::source_path("studies/gimbal_unbalance_mc.toml");
  auto g1 = poise::test::run_poise(d, "run '" + g + "' --samples 24 -q --no-plots --out '" + d.file("g1") + "'");
  ASSERT_EQ(g1.status, 0) << g1.err;
  const std::string mpi_g = kMpiRootEnv + std::string("'") + POISE_MPIEXEC + "' --allow-run-as-root --oversubscribe -np 2 '" +
                            ::poise::test::poise_binary() + "' run '" + g + "' --samples 24 -q --no-plots --threads 1 --out '" +
                            d.file("g2") + "' >'" + d.file("mpi_g.txt") + "' 2>&1";
  const int raw_g = std::system(mpi_g.c_str());
  ASSERT_TRUE(WIFEXITED(raw_g) && WEXITSTATUS(raw_g) == 0) << poise::test::read_text(d.file("mpi_g.txt"));
  EXPECT_EQ(poise::test::read_text(d.file("g1/samples.csv")), poise::test::read_text(d.file("g2/samples.csv")));
  EXPECT_EQ(comparable(d.file("g1")), comparable(d.file("g2")));
#endif
}

TEST(Mpi, AnOutFolderHoldingARunIsRefusedOnEveryRank) {
#if !defined(POISE_MPIEXEC) || !defined(POISE_BUILT_WITH_MPI)
  GTEST_SKIP() << "needs mpirun and poise built with MPI (see TwoRanksGiveTheSamplesAndStatisticsOfOneProcess)";
#else
  // Rank 0 makes the run's folder: its refusal is every rank's, and no rank waits for the run
  // (it hung until killed). `timeout` ends a hang here as a failure, not a stuck test.
  TempDir d;
  const std::string study = seeker_study(d);
  auto first = poise::test::run_poise(d, "run '" + study + "' --samples 64 -q --no-plots --out '" + d.file("r") + "'");
  ASSERT_EQ(first.status, 0) << first.err;
  const std::string mpi = kMpiRootEnv + std::string("timeout 120 '") + POISE_MPIEXEC +
                          "' --allow-run-as-root --oversubscribe -np 2 '" + ::poise::test::poise_binary() + "' run '" + study +
                          "' --samples 64 -q --no-plots --threads 1 --out '" + d.file("r") + "' >'" +
                          d.file("mpi_out.txt") + "' 2>&1";
  const int raw = std::system(mpi.c_str());
  const std::string out = poise::test::read_text(d.file("mpi_out.txt"));
  ASSERT_TRUE(WIFEXITED(raw)) << out;
  EXPECT_EQ(WEXITSTATUS(raw), 2) << out;  // 124: timeout killed a hang
  EXPECT_NE(out.find("already holds a run"), std::string::npos) << out;
#endif
}

TEST(Mpi, SweepsAndContributionsSpreadOverRanksGiveOneProcessesTables) {
#if !defined(POISE_MPIEXEC) || !defined(POISE_BUILT_WITH_MPI)
  GTEST_SKIP() << "needs mpirun and poise built with MPI (see TwoRanksGiveTheSamplesAndStatisticsOfOneProcess)";
#else
  // Each sweep value and each contribution run is a whole run made on one rank, the next one
  // free when a rank is ready (engine/run/runs_over_ranks.h): three ranks for five sweep runs
  // and the contribution runs, whichever rank makes which.
  TempDir d;
  std::string text = poise::test::read_text(seeker_study(d));
  text += "contribution_samples = 128\n\n[[sweep]]\nparameter = \"yaw.bearing_span\"\n"
          "values = [\"56 mm\", \"82 mm\", \"120 mm\"]\nsamples = 128\n\n[[sweep]]\n"
          "parameter = \"pitch.bearing_span\"\nvalues = [\"40 mm\", \"70 mm\"]\nsamples = 96\n";
  text = poise::test::replace_once(text, "contribution_samples = 0\n", "");
  poise::test::write_text(d.file("sweeps.toml"), text);
  const std::string args = "run '" + d.file("sweeps.toml") + "' --samples 300 -q --no-plots";
  auto one = poise::test::run_poise(d, args + " --out '" + d.file("one") + "'");
  ASSERT_EQ(one.status, 0) << one.err;
  const std::string mpi = kMpiRootEnv + std::string("'") + POISE_MPIEXEC + "' --allow-run-as-root --oversubscribe -np 3 '" +
                          ::poise::test::poise_binary() + "' " + args + " --threads 1 --out '" + d.file("three") + "' >'" +
                          d.file("mpi_out.txt") + "' 2>&1";
  const int raw = std::system(mpi.c_str());
  ASSERT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) == 0) << poise::test::read_text(d.file("mpi_out.txt"));
  const json s1 = comparable(d.file("one")), s3 = comparable(d.file("three"));
  ASSERT_EQ(s1["sweeps"].size(), 2u) << s1.dump();
  EXPECT_EQ(s1["sweeps"][0]["points"].size(), 3u);
  ASSERT_GE(s1["contributions"].size(), 3u) << s1.dump();
  EXPECT_EQ(s1["sweeps"], s3["sweeps"]);
  EXPECT_EQ(s1["contributions"], s3["contributions"]);
  EXPECT_EQ(s1, s3);
#endif
}

}  // namespace
