// One exit status for each kind of failure, the same in every command (issue 20): 0 success,
// 2 invalid input or command line (CLI11's own errors included), 1 a run that failed,
// 128 + signal interrupted. A refused command creates nothing on disk.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/run/convergence.h"
#include "engine/run/study_runner.h"
#include "sampling/interrupt.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using poise::test::TempDir;
using poise::test::run_poise;
using poise::test::source_path;

std::string quoted(const std::string& path) { return "'" + path + "'"; }

TEST(ExitStatus, HelpAndVersionAreSuccess) {
  TempDir d;
  auto r = run_poise(d, "--help");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("Exit status, the same for every command"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("128 + N"), std::string::npos);
  r = run_poise(d, "run --help");
  EXPECT_EQ(r.status, 0) << r.err;
  r = run_poise(d, "--version");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("poise "), std::string::npos);
}

TEST(ExitStatus, CommandLineMistakesAreTwoInEveryCommand) {
  // CLI11 has its own codes (105 a bad value, 106 a missing argument, 109 an extra one): Poise
  // answers 2 for each, with CLI11's message.
  TempDir d;
  const std::vector<std::string> commands = {"run", "sensitivity", "validate", "replay", "fit", "diagnose",
                                             "simulate-record", "diagnose-record", "optimize", "keys", "budget",
                                             "mass-properties"};
  for (const auto& c : commands) {
    SCOPED_TRACE(c);
    const auto r = run_poise(d, c + " --no-such-option");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_FALSE(r.err.empty());  // the command's first mistake: CLI11's message or the command's
    EXPECT_LT(r.err.size(), 400u) << r.err;
  }
  auto r = run_poise(d, "");  // no command at all
  EXPECT_EQ(r.status, 2) << r.err;
  r = run_poise(d, "validate " + quoted(d.file("missing.toml")));  // CLI11 ExistingFile (105)
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("missing.toml"), std::string::npos) << r.err;
  r = run_poise(d, "replay " + quoted(source_path("studies/los_seeker_wang2011.toml")));  // --sample missing (106)
  EXPECT_EQ(r.status, 2) << r.err;
  r = run_poise(d, "validate a.toml b.toml");  // an extra argument (109)
  EXPECT_EQ(r.status, 2) << r.err;
}

TEST(ExitStatus, ZeroSamplesGetAShortClearMessage) {
  TempDir d;
  const auto r = run_poise(d, "run " + quoted(source_path("studies/los_seeker_wang2011.toml")) + " --samples 0 -q");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("must be a whole number of at least 1, got \"0\""), std::string::npos) << r.err;
  EXPECT_LT(r.err.size(), 300u) << r.err;  // not a 309-digit range
  const auto neg = run_poise(d, "sensitivity " + quoted(source_path("studies/los_seeker_wang2011.toml")) + " --base -3");
  EXPECT_EQ(neg.status, 2) << neg.err;
}

TEST(ExitStatus, RefusedRunsAreTwoAndCreateNothing) {
  TempDir d;
  const std::string study = quoted(source_path("studies/los_seeker_wang2011.toml"));
  // An --until that names no output: refused before the result folder exists.
  const std::string replicates = quoted(source_path("studies/los_seeker_wang2011_replicates.toml"));
  auto r = run_poise(d, "run " + replicates + " --until 'nothing.p95<=1' -q --no-plots --results-root " +
                            quoted(d.file("results")) + " --out " + quoted(d.file("u")));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("no output \"nothing\""), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d.file("u")));
  r = run_poise(d, "run " + study + " --until 'los_max_arcsec.p95<=1' -q --results-root " + quoted(d.file("results")));
  EXPECT_EQ(r.status, 2) << r.err;  // a Sobol design without replicates cannot grow
  EXPECT_FALSE(fs::exists(d.file("results")));
  // A replay past the run's end.
  r = run_poise(d, "replay " + study + " --sample 99999999");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("outside 0.."), std::string::npos) << r.err;
  // --out into a folder that holds a run.
  poise::test::write_text(d.file("held/samples.csv"), "sample,status\n");
  r = run_poise(d, "run " + study + " --samples 4 -q --no-plots --out " + quoted(d.file("held")));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("already holds a run"), std::string::npos) << r.err;
  EXPECT_EQ(poise::test::read_text(d.file("held/samples.csv")), "sample,status\n");
  // The same for an optimization's --out.
  r = run_poise(d, "optimize " + quoted(source_path("studies/bearing_span_sizing.toml")) + " -q --no-plots --out " +
                       quoted(d.file("held")));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("already holds a run"), std::string::npos) << r.err;
  // --resume of a folder that is no run.
  r = run_poise(d, "run --resume " + quoted(d.file("held")) + " -q");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("no run.json"), std::string::npos) << r.err;
  // run without a study and without --resume.
  r = run_poise(d, "run -q");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("STUDY is required"), std::string::npos) << r.err;
}

TEST(ExitStatus, InvalidInputIsTwoInEveryCommandThatReadsAFile) {
  // One refused input file per command: a file that is not what the command reads.
  TempDir d;
  const std::string bad = d.file("bad.toml");
  poise::test::write_text(bad, "not = [toml\n");
  const std::string csv = d.file("bad.csv");
  poise::test::write_text(csv, "a,b\n1,2\n");
  const std::vector<std::string> commands = {
      "validate " + quoted(bad), "run " + quoted(bad) + " -q", "sensitivity " + quoted(bad) + " --base 4 -q",
      "replay " + quoted(bad) + " --sample 0", "optimize " + quoted(bad), "budget " + quoted(bad),
      "fit " + quoted(csv), "diagnose-record " + quoted(csv) + " --kt '0.5 N*m/A'",
      "mass-properties " + quoted(csv) + " --unit mm --density '2700 kg/m^3'"};
  for (const auto& c : commands) {
    SCOPED_TRACE(c);
    const auto r = run_poise(d, c);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("bad."), std::string::npos) << "names the file:\n" << r.err;
  }
  const auto k = run_poise(d, "keys no_such_kind");
  EXPECT_EQ(k.status, 2) << k.err;
}

TEST(ExitStatus, TheIssuesDeepNestingIsRefusedByEveryCommandThatReadsToml) {
  // The 50,000-level dotted key and table header that overflowed toml++'s stack (issue 20),
  // as a study, an optimization file and a budget file: exit 2 with the file and its line.
  TempDir d;
  for (const char* file : {"deeply_dotted_key.toml", "deeply_nested_header.toml"}) {
    const std::string path = poise::test::source_path(std::string("tests/data/malformed/") + file);
    for (const std::string& c : {"validate " + quoted(path), "optimize " + quoted(path) + " -q",
                                 "budget " + quoted(path)}) {
      SCOPED_TRACE(c);
      const auto r = run_poise(d, c);
      EXPECT_EQ(r.status, 2) << r.err;
      EXPECT_NE(r.err.find(std::string(file) + ":"), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("nested at most 64 levels deep"), std::string::npos) << r.err;
      EXPECT_LT(r.err.size(), 2000u);
    }
  }
}

TEST(ExitStatus, ResumeWithoutTheStudyPathReadsRunJson) {
  // run.json names the study file: `poise run --resume DIR` needs nothing else.
  TempDir d;
  const std::string study = quoted(source_path("studies/gimbal_unbalance_mc.toml"));
  auto r = run_poise(d, "run " + study + " --samples 6 --threads 1 -q --no-plots --out " + quoted(d.file("a")));
  ASSERT_EQ(r.status, 0) << r.err;
  json manifest = json::parse(poise::test::read_text(d.file("a/run.json")));
  EXPECT_EQ(manifest["study_file"], fs::absolute(source_path("studies/gimbal_unbalance_mc.toml")).string());
  // Cut the run to its first 3 samples, as an interruption would leave it.
  const std::string csv = poise::test::read_text(d.file("a/samples.csv"));
  std::size_t pos = 0;
  for (int line = 0; line < 4; ++line) pos = csv.find('\n', pos) + 1;
  poise::test::write_text(d.file("a/samples.csv"), csv.substr(0, pos));
  fs::remove(d.file("a/summary.json"));
  manifest["status"] = "interrupted";
  poise::test::write_text(d.file("a/run.json"), manifest.dump(2));
  r = run_poise(d, "run --resume " + quoted(d.file("a")) + " -q --no-plots");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(poise::test::read_text(d.file("a/samples.csv")), csv);
  EXPECT_EQ(json::parse(poise::test::read_text(d.file("a/run.json")))["status"], "complete");
}

TEST(ExitStatus, ASignalWhileTheResultsAreWrittenIsHonoured) {
  // Every sample ran, then Ctrl-C arrived during the summary write: the run is complete, and
  // the exit status still says it was stopped (128 + 2). Forked: the signal flag stays set.
  const pid_t pid = fork();
  if (pid == 0) {
    int code = 0;
    {
      poise::sampling::InterruptGuard guard;
      std::raise(SIGINT);
      try {
        poise::engine::finish_run_status("complete", "", 0, 10, 10, 0, "/tmp/run", "study.toml");
      } catch (const poise::engine::Interrupted& e) {
        code = std::string(e.what()).find("the run is complete") != std::string::npos ? 128 + e.signal : 1;
      }
    }
    _exit(code);
  }
  int st = 0;
  waitpid(pid, &st, 0);
  ASSERT_TRUE(WIFEXITED(st));
  EXPECT_EQ(WEXITSTATUS(st), 130);
}

}  // namespace
