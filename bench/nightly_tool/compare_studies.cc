// compare: the reference-study section of the report. Each study's samples against its one
// recorded reference (tests/data/study_reference/, the files study_reference_test compares
// with; bench/nightly writes the verdict into the run file), wall times against the previous run.
#include <cstdio>
#include <string>

#include "compare.h"

namespace poise::nightly {

void compare_studies(const json& cur, const json& prev, const json& ref, const TimingRules& rules) {
  const Options& opt = rules.opt;
  Tally& t = rules.t;
  const json cs = cur.value("studies", json::object());
  const json ps = prev.is_object() ? prev.value("studies", json::object()) : json::object();
  std::printf(
      "\nreference studies (samples against their recorded reference, tests/data/study_reference/; wall time "
      "against the previous run, warning beyond %s)\n",
      pct(opt.wall_warn).c_str());
  if (ref.is_object() && ref.contains("studies")) {
    std::printf("note: the reference file's study statistics are not used: each study has one recorded reference, "
                "in tests/data/study_reference/\n");
  }
  for (const auto& [name, e] : cs.items()) {
    std::printf("%s: %s samples, seed %s, wall %s s", name.c_str(), e.value("samples", json()).dump().c_str(),
                e.value("seed", json()).dump().c_str(), fmt(e.value("wall_s", 0.0)).c_str());
    if (rules.times_vs_previous && ps.contains(name) && num(ps[name], "wall_s") &&
        ps[name].value("samples", json()) == e.value("samples", json())) {
      const double pw = ps[name]["wall_s"].get<double>(), w = e.value("wall_s", 0.0);
      std::printf(" (previous %s s, x%s)", fmt(pw).c_str(), ratio_str(w / pw).c_str());
      if (pw > 0 && w / pw - 1.0 > opt.wall_warn) std::printf(" slower (warning)"), ++t.warnings;
    }
    std::printf("\n");
    if (e.value("exit_status", 0) != 0 || e.contains("error")) {
      std::printf("  FAILED: exit status %d %s\n", e.value("exit_status", 0), e.value("error", std::string()).c_str());
      t.regressions.push_back("study " + name + " failed");
      continue;
    }
    if (!e.value("failures", json()).is_null() && e.value("failures", 0) != 0) {
      std::printf("  REGRESSION: %d failed samples\n", e.value("failures", 0));
      t.regressions.push_back("study " + name + ": failed samples");
    }
    if (!e.contains("reference") || !e["reference"].is_object()) {
      std::printf("  not checked: the run file has no verdict against the recorded reference (an older bench/nightly) "
                  "(warning)\n");
      ++t.warnings;
      continue;
    }
    const json& r = e["reference"];
    const std::string file = r.value("file", std::string("tests/data/study_reference/" + name));
    const std::string verdict = r.value("verdict", std::string("missing: no verdict"));
    ++t.compared;
    if (verdict == "same") {
      std::printf("  samples equal the recorded reference %s\n", file.c_str());
      continue;
    }
    std::printf(
        "  REGRESSION: %s (recorded reference %s). If the change is deliberate, re-record it "
        "(tests/data/study_reference/record.sh build/poise %s) and say why in the commit\n",
        verdict.c_str(), file.c_str(), name.c_str());
    t.regressions.push_back("study " + name + ": " + verdict);
  }
}

}  // namespace poise::nightly
