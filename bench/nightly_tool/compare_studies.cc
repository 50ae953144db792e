// compare: the reference-study section of the report (fixed-seed statistics against the
// reference, wall times against the previous run).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "compare.h"

namespace poise::nightly {

void compare_studies(const json& cur, const json& prev, const json& ref, const TimingRules& rules) {
  const Options& opt = rules.opt;
  Tally& t = rules.t;
  const json cs = cur.value("studies", json::object());
  const json ps = prev.is_object() ? prev.value("studies", json::object()) : json::object();
  const json rs = ref.is_object() ? ref.value("studies", json::object()) : json::object();
  std::printf(
      "\nreference studies (statistics against the reference, relative tolerance %.0e; wall time against "
      "the previous run, warning beyond %s)\n",
      opt.stat_rtol, pct(opt.wall_warn).c_str());
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
    if (!rs.contains(name)) {
      std::printf("  not in the reference (warning: not checked)\n");
      if (!ref.is_null()) ++t.warnings;
      continue;
    }
    const json& r = rs[name];
    if (r.value("samples", json()) != e.value("samples", json()) ||
        r.value("seed", json()) != e.value("seed", json())) {
      std::printf(
          "  REGRESSION: settings differ from the reference (samples %s seed %s there): not comparable; "
          "update the reference deliberately (bench/nightly --update-reference)\n",
          r.value("samples", json()).dump().c_str(), r.value("seed", json()).dump().c_str());
      t.regressions.push_back("study " + name + ": settings differ from the reference");
      continue;
    }
    for (const char* sha : {"study_file_sha1", "model_file_sha1"}) {
      if (r.contains(sha) && e.contains(sha) && r[sha] != e[sha])
        std::printf("  note: %s changed since the reference\n", sha);
    }
    int n = 0, changed = 0;
    const json rstats = r.value("statistics", json::object()), cstats = e.value("statistics", json::object());
    bool header = false;
    for (const auto& [out_name, rstat] : rstats.items()) {
      for (const auto& [stat, rv] : rstat.items()) {
        const std::string label = out_name + "." + stat;
        const json cv = cstats.contains(out_name) ? cstats[out_name].value(stat, json("missing")) : json("missing");
        ++n, ++t.compared;
        bool same;
        double rel = 0;
        if (rv.is_number() && cv.is_number()) {
          const double a = rv.get<double>(), b = cv.get<double>();
          const double scale = std::max(std::abs(a), std::abs(b));
          rel = scale > 0 ? std::abs(a - b) / scale : 0.0;
          same = rel <= opt.stat_rtol;
        } else {
          same = rv == cv;
        }
        if (!same) {
          ++changed;
          t.regressions.push_back("study " + name + ": " + label + " changed");
        }
        if (!same || opt.all) {
          if (!header) {
            std::printf("  %-44s %20s %20s %10s  %s\n", "statistic", "reference", "current", "rel diff", "verdict");
            header = true;
          }
          std::printf("  %-44s %20s %20s %10s  %s\n", label.c_str(),
                      rv.is_number() ? full(rv.get<double>()).c_str() : rv.dump().c_str(),
                      cv.is_number() ? full(cv.get<double>()).c_str() : cv.dump().c_str(),
                      rv.is_number() && cv.is_number() ? fmt(rel).c_str() : "-", same ? "ok" : "CHANGED");
        }
      }
    }
    int unreferenced = 0;
    for (const auto& [out_name, cstat] : cstats.items()) {
      if (!rstats.contains(out_name)) {
        std::printf("  %-44s new output, not in the reference (warning)\n", out_name.c_str()), ++t.warnings;
        continue;
      }
      for (const auto& [stat, cv] : cstat.items()) unreferenced += rstats[out_name].contains(stat) ? 0 : 1;
    }
    if (unreferenced > 0) {
      std::printf("  note: %d figures (interval ends) have no reference figure: not compared "
                  "(bench/nightly --update-reference records them)\n", unreferenced);
    }
    std::printf("  %d statistics compared, %d changed%s\n", n, changed,
                changed ? " (REGRESSION: the physics or the "
                          "sampling changed; if deliberate, bench/nightly --update-reference)"
                        : ", all equal to the reference");
  }
  for (const auto& [name, r] : rs.items()) {
    if (!cs.contains(name)) {
      std::printf("%s: in the reference, missing in the current run (REGRESSION)\n", name.c_str());
      t.regressions.push_back("study " + name + " missing");
    }
  }
}

}  // namespace poise::nightly
