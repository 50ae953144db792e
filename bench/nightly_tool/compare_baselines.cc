// compare: the baseline-ratio section of the report (NumPy/SciPy CPU time over Poise's, from
// bench/baselines/compare.py in the same run).
#include <cstdio>
#include <string>
#include <vector>

#include "compare.h"

namespace poise::nightly {

void compare_baselines(const json& cur, const json& prev, const json& ref, const Options& opt, Tally& t) {
  const auto ran = [](const json& run) {
    const json b = run.is_object() ? run.value("baselines", json::object()) : json::object();
    return b.value("status", std::string()) == "ran" ? b : json();
  };
  std::printf(
      "\nbaselines: ratios of CPU time, NumPy/SciPy over Poise in the same run (higher = Poise faster); a regression "
      "below previous or reference / %s\n",
      fmt(1.0 + opt.ratio_band).c_str());
  const json cb = cur.value("baselines", json());
  const json rb = ref.is_object() ? ref.value("baselines", json::object()) : json::object();
  const json rr = rb.value("ratios", json::object());
  if (!cb.is_object() || cb.value("status", std::string()) != "ran") {
    const std::string reason = cb.is_object() ? cb.value("reason", std::string("no reason given"))
                                              : std::string("no \"baselines\" in the run file");
    std::printf("  not run: %s (warning: %s)\n", reason.c_str(),
                rr.empty() ? "nothing checked" : "the reference's ratios not checked");
    ++t.warnings;
    return;
  }
  // compare.py --quick times for 0.1-0.2 s and scans one LSODA tolerance: its ratios only warn,
  // with or without --warn-timing.
  const bool warn_only = opt.warn_timing || cb.value("quick", false);
  const json pb = ran(prev);
  const json pr = pb.is_object() ? pb.value("ratios", json::object()) : json::object();
  const auto load = [](const json& v) { return v.is_array() && !v.empty() ? v.dump() : std::string("?"); };
  std::printf("  %s samples%s; load average %s before, %s after\n", cb.value("samples", json()).dump().c_str(),
              cb.value("quick", false) ? ", quick" : "", load(cb.value("load_avg_start", json())).c_str(),
              load(cb.value("load_avg_end", json())).c_str());
  // Whole-run and compute ratios depend on the sample count: other counts are not compared.
  const bool prev_comparable = pb.is_object() && pb.value("samples", json()) == cb.value("samples", json());
  const bool ref_comparable = !rb.contains("samples") || rb.value("samples", json()) == cb.value("samples", json());
  if (!prev.is_null() && !pb.is_object()) std::printf("  note: the previous run has no baseline ratios\n");
  if (pb.is_object() && !prev_comparable) std::printf("  note: the previous run used another sample count: not compared\n");
  if (!rr.empty() && !ref_comparable) std::printf("  note: the reference used another sample count: not compared\n");
  std::printf("  %-22s %10s %10s %10s %12s %8s %8s  %s\n", "ratio", "previous", "current", "reference", "target",
              "cur/prev", "cur/ref", "verdict");
  const json cr_all = cb.value("ratios", json::object());  // named: items() keeps a reference
  for (const auto& [key, e] : cr_all.items()) {
    std::vector<std::string> verdicts;
    const auto v = num(e, "value");
    std::string ps = "-", rs = "-", ts = "-", cp = "-", cr = "-";
    const auto tmin = num(e.value("target", json::object()), "min");
    if (tmin) ts = ">= " + fmt(*tmin);
    if (!v || *v <= 0) {
      std::printf("  %-22s %10s %10s %10s %12s %8s %8s  no ratio: %s (warning)\n", key.c_str(), ps.c_str(), "-",
                  rs.c_str(), ts.c_str(), cp.c_str(), cr.c_str(), e.value("reason", std::string("not computed")).c_str());
      ++t.warnings;
      continue;
    }
    if (tmin && *v < *tmin) verdicts.push_back("below target (warning)"), ++t.warnings;
    const auto against = [&](const json& other, const char* what, std::string& shown, std::string& ratio) {
      const auto ov = num(other, "value");
      if (!ov || *ov <= 0) return false;
      shown = fmt(*ov), ratio = ratio_str(*v / *ov);
      ++t.compared;
      const Verdict vd = judge(*v, *ov, false, opt.ratio_band);
      if (vd.regression) {
        const std::string msg = "baseline ratio " + key + " vs " + what + " (" + fmt(*ov) + "x -> " + fmt(*v) + "x)";
        if (warn_only)
          ++t.warnings, verdicts.push_back(std::string("REGRESSION vs ") + what + " (warning)");
        else
          t.regressions.push_back(msg), verdicts.push_back(std::string("REGRESSION vs ") + what);
      } else if (vd.text == "better") {
        verdicts.push_back(std::string("better vs ") + what);
      }
      return true;
    };
    if (prev_comparable && pr.contains(key)) against(pr[key], "previous", ps, cp);
    if (!ref.is_null()) {
      if (!ref_comparable || !rr.contains(key) || !against(rr[key], "reference", rs, cr))
        verdicts.push_back(ref_comparable ? "no reference ratio" : "reference not comparable");
    }
    std::string verdict;
    for (const auto& x : verdicts) verdict += (verdict.empty() ? "" : ", ") + x;
    if (verdict.empty()) verdict = tmin ? "meets target" : "ok";
    std::printf("  %-22s %10s %10s %10s %12s %8s %8s  %s\n", key.c_str(), ps.c_str(), fmt(*v).c_str(), rs.c_str(),
                ts.c_str(), cp.c_str(), cr.c_str(), verdict.c_str());
  }
  for (const auto& [key, e] : rr.items()) {
    if (!cr_all.contains(key)) {
      std::printf("  %-22s in the reference, missing in the current run (warning)\n", key.c_str());
      ++t.warnings;
    }
  }
}

}  // namespace poise::nightly
