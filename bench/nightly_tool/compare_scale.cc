// compare: the section of a LOS run at scale (bench/los_scale --json in the same nightly): the
// peak memory of a large run against its target and the previous run, the whole study's 1 -> 2
// thread speed-up against its target, rank 0's memory under MPI and the equality of its data.
#include <cstdio>
#include <string>

#include "compare.h"

namespace poise::nightly {

void compare_scale(const json& cur, const json& prev, const TimingRules& rules) {
  const json cs = cur.value("scale", json());
  const json ps = prev.is_object() ? prev.value("scale", json()) : json();
  if (cs.is_null() && (ps.is_null() || !ps.is_object())) return;  // neither run has one: nothing to say
  Tally& t = rules.t;
  const Options& opt = rules.opt;
  std::printf("\nLOS run at scale (bench/los_scale): peak memory against its target and the previous run (a "
              "regression beyond x%s at the same sample count), speed-up and MPI against their targets\n",
              fmt(1.0 + opt.memory_band).c_str());
  if (!cs.is_object() || cs.value("status", std::string()) != "ran") {
    const std::string reason = cs.is_object() ? cs.value("reason", std::string("no reason given"))
                                              : std::string("no \"scale\" in the run file");
    std::printf("  not run: %s (warning)\n", reason.c_str());
    ++t.warnings;
    return;
  }
  if (cs.value("exit_status", 0) == 1) {
    std::printf("  FAILED: a run of bench/los_scale failed\n");
    t.regressions.push_back("bench/los_scale: a run failed");
  }
  const bool prev_ran = ps.is_object() && ps.value("status", std::string()) == "ran";

  if (const json m = cs.value("memory", json()); m.is_object()) {
    const double rss = m.value("peak_rss_mb", 0.0), target = m.value("target_peak_rss_mb", 400.0);
    std::printf("  memory: %s samples, %s threads: peak RSS %s MB (target < %s MB), %s CPU-s, %s s wall; load %s\n",
                m.value("samples", json()).dump().c_str(), m.value("threads", json()).dump().c_str(), fmt(rss).c_str(),
                fmt(target).c_str(), fmt(m.value("cpu_s", 0.0)).c_str(), fmt(m.value("wall_s", 0.0)).c_str(),
                fmt(m.value("load_before", 0.0)).c_str());
    if (!(rss < target)) {
      std::printf("    above its target (warning)\n");
      ++t.warnings;
    }
    const json pm = prev_ran ? ps.value("memory", json()) : json();
    if (pm.is_object() && pm.value("samples", json()) == m.value("samples", json()) && pm.value("peak_rss_mb", 0.0) > 0) {
      const double before = pm["peak_rss_mb"].get<double>();
      ++t.compared;
      std::printf("    previous %s MB: x%s", fmt(before).c_str(), ratio_str(rss / before).c_str());
      if (rss > before * (1.0 + opt.memory_band)) {
        std::printf("  REGRESSION\n");
        t.regressions.push_back("LOS run peak memory (" + fmt(before) + " -> " + fmt(rss) + " MB)");
      } else {
        std::printf("  ok\n");
      }
    }
  }

  if (const json s = cs.value("scaling", json()); s.is_object()) {
    const double speedup = s.value("speedup", 0.0), target = s.value("target_speedup", 1.85);
    std::printf("  scaling: %s samples, the whole study 1 -> 2 threads: %sx by wall time (%s and %s s; target %s)",
                s.value("samples", json()).dump().c_str(), fmt(speedup).c_str(), fmt(s.value("wall_1_s", 0.0)).c_str(),
                fmt(s.value("wall_2_s", 0.0)).c_str(), fmt(target).c_str());
    const std::string loaded = rules.too_loaded(json{{"load_avg", s.value("load_before_2", 0.0)}});
    if (!loaded.empty()) {
      std::printf("  %s\n", loaded.c_str());
    } else if (speedup < target) {
      std::printf("  below target (warning)\n");
      ++t.warnings;
    } else {
      std::printf("  meets target\n");
    }
  }

  if (const json p = cs.value("mpi", json()); p.is_object()) {
    const double growth = p.value("rank0_growth_mb", 0.0), target = p.value("target_growth_mb", 32.0);
    std::printf("  mpi: %s samples, %zu rank counts: rank 0 grew %s MB from the fewest ranks to the most (target <= %s)",
                p.value("samples", json()).dump().c_str(), p.value("runs", json::array()).size(),
                fmt(growth).c_str(), fmt(target).c_str());
    if (growth > target) {
      std::printf("  above its target (warning)");
      ++t.warnings;
    }
    ++t.compared;
    if (!p.value("digests_equal", false)) {
      std::printf("; samples.h5 values DIFFER between rank counts: REGRESSION\n");
      t.regressions.push_back("LOS run under MPI: samples.h5 values differ between rank counts");
    } else {
      std::printf("; the same samples.h5 values at every rank count\n");
    }
  }
}

}  // namespace poise::nightly
