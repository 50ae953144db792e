// The external kind (src/kinds/external/): a program of the user's own, spoken to through its
// standard input and output. It runs only when allowed, gives the same samples as the same
// arithmetic written as formulas, and a sample it fails, a crash or a silence fails only the
// samples it left unanswered, with the reason and the program's standard error; the run goes on.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "test_util.h"

namespace poise {
namespace {
using test::read_text;
using test::TempDir;

// The stack in SI units (factor 1: the program's numbers are Poise's, bit for bit).
const char* kParameters = R"TOML(
[parameters]
housing = "0.060 m"
bearing_a = "0.016 m"
spacer = "0.0276 m"
bearing_b = "0.016 m"
[tolerances.housing]
tolerance = "0.00005 m"
distribution = "normal"
tolerance_is = "3sigma"
[tolerances.bearing_a]
deviation = ["-0.00012 m", "0 m"]
distribution = "normal"
tolerance_is = "3sigma"
[tolerances.spacer]
tolerance = "0.00003 m"
distribution = "uniform"
tolerance_is = "bounds"
)TOML";

// The program: the gap, and what a test asks of it at a given sample ("fail", "crash", "hang").
std::string program(const std::string& at_sample_5) {
  return R"PY(import json, sys, time
for line in sys.stdin:
    r = json.loads(line)
    x = r["inputs"]
    if r["sample"] == 5 and ")PY" +
         at_sample_5 + R"PY(" == "fail":
        print(json.dumps({"sample": 5, "failed": "the rings interfere"}), flush=True)
        continue
    if r["sample"] == 5 and ")PY" +
         at_sample_5 + R"PY(" == "crash":
        sys.stderr.write("Traceback: something broke at sample 5\n")
        sys.exit(3)
    if r["sample"] == 5 and ")PY" +
         at_sample_5 + R"PY(" == "hang":
        time.sleep(3600)
    print(json.dumps({"sample": r["sample"], "outputs": {"gap": x["housing"] - (x["bearing_a"] + x["spacer"] + x["bearing_b"])}}), flush=True)
)PY";
}

void write_models(TempDir& dir, const std::string& at_sample_5, const std::string& timeout = "60 s") {
  test::write_text(dir.file("model.py"), program(at_sample_5));
  test::write_text(dir.file("external.toml"),
                   std::string("[model]\nkind = \"external\"\nname = \"stack\"\ncommand = [\"python3\", \"model.py\"]\n"
                               "batch = 4\ntimeout = \"") +
                       timeout + "\"\n" + kParameters + "[[output]]\nname = \"gap\"\nunit = \"m\"\n");
  test::write_text(dir.file("formula.toml"),
                   std::string("[model]\nkind = \"formula\"\nname = \"stack\"\n") + kParameters +
                       "[[output]]\nname = \"gap\"\nunit = \"m\"\nformula = \"housing - (bearing_a + spacer + bearing_b)\"\n");
  for (const char* kind : {"external", "formula"}) {
    test::write_text(dir.file(std::string("study_") + kind + ".toml"),
                     std::string("[study]\nname = \"s\"\nkind = \"") + kind + "\"\nmodel = \"" + kind +
                         ".toml\"\n[sampling]\nmethod = \"monte_carlo\"\nsamples = 40\nseed = 5\n"
                         "max_failure_share = 0.5\n");
  }
}

test::RunResult run(TempDir& dir, const std::string& kind, const std::string& flags = "--allow-programs") {
  return test::run_poise(dir, "run '" + dir.file("study_" + kind + ".toml") + "' " + flags +
                                  " --threads 2 --quiet --no-plots --out '" + dir.file("run_" + kind) + "'");
}

TEST(ExternalKind, RunsOnlyWhenAllowedAndValidateShowsTheCommand) {
  TempDir dir;
  write_models(dir, "none");
  const auto refused = run(dir, "external", "");
  EXPECT_EQ(refused.status, 2);
  EXPECT_NE(refused.err.find("runs a program of its own: python3 model.py"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("--allow-programs"), std::string::npos) << refused.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("run_external") + "/samples.csv"));
  const auto v = test::run_poise(dir, "validate '" + dir.file("study_external.toml") + "'");
  EXPECT_EQ(v.status, 0) << v.err;
  EXPECT_NE(v.out.find("runs the program python3 model.py (in " + dir.path().string()), std::string::npos) << v.out;
}

TEST(ExternalKind, GivesTheFormulasSamplesBitForBit) {
  TempDir dir;
  write_models(dir, "none");
  ASSERT_EQ(run(dir, "external").status, 0);
  ASSERT_EQ(run(dir, "formula").status, 0);
  EXPECT_EQ(read_text(dir.file("run_external") + "/samples.csv"), read_text(dir.file("run_formula") + "/samples.csv"));
}

// Sample 5 is answered "failed", crashes the program, or is never answered (a timeout of 2 s: the
// program sleeps an hour; its other answers take microseconds, and the first after a start has
// 10 s more, so the outcome does not depend on the machine's speed or load).
TEST(ExternalKind, AFailedCrashedOrSilentProgramFailsOnlyWhatItLeftUnanswered) {
  struct Case {
    std::string what, reason;
    std::size_t failed;
  };
  for (const Case& c : {Case{"fail", "the program: the rings interfere", 1},
                        Case{"crash", "the program ended (exit status 3)", 3},
                        Case{"hang", "no answer within 2", 3}}) {
    TempDir dir;
    write_models(dir, c.what, "2 s");
    const auto r = run(dir, "external");
    ASSERT_EQ(r.status, 0) << c.what << ": " << r.err;
    const auto s = nlohmann::json::parse(read_text(dir.file("run_external") + "/summary.json"));
    EXPECT_EQ(s["failures"]["count"].get<std::size_t>(), c.failed) << c.what;
    const std::string csv = read_text(dir.file("run_external") + "/samples.csv");
    EXPECT_NE(csv.find("5,failed"), std::string::npos) << c.what;
    EXPECT_NE(csv.find(c.reason), std::string::npos) << c.what << "\n" << csv.substr(0, 1500);
    if (c.what == "crash") {
      EXPECT_NE(csv.find("something broke at sample 5"), std::string::npos);
    }
    EXPECT_NE(csv.find("8,ok"), std::string::npos) << c.what;  // the next batch, by a new process
  }
}

}  // namespace
}  // namespace poise
