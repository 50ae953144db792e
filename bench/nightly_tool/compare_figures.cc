// compare: the benchmark and derived-figure sections of the report and the timing rules that
// judge them (TimingRules, compare.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "compare.h"

namespace poise::nightly {

bool TimingRules::gross(double worse, double band) const { return worse > std::max(2.0 * band, opt.gross); }

void TimingRules::flag_timing(const std::string& what, double worse, double band) const {
  if (opt.warn_timing && !gross(worse, band))
    ++t.warnings;
  else
    t.regressions.push_back(what);
}

std::string TimingRules::warn_suffix(const Verdict& v, double worse, double band) const {
  return v.regression && opt.warn_timing && !gross(worse, band) ? std::string(" (warning)") : std::string();
}

std::string TimingRules::too_loaded(const json& e) const {
  if (!e.contains("load_avg") || !e["load_avg"].is_number() || cores <= 0) return "";
  const double load = e["load_avg"].get<double>();
  if (load < cores - 1 + opt.idle_margin) return "";
  char buf[96];
  std::snprintf(buf, sizeof buf, "not judged: load %.2f on %d cores", load, cores);
  ++t.not_judged;
  return buf;
}

double TimingRules::band_of(double n1, double n2) const { return std::max(opt.floor, opt.k * std::hypot(n1, n2)); }

void compare_benchmarks(const json& cur, const json& prev, const json& ref, const TimingRules& rules) {
  Tally& t = rules.t;
  const json cb = cur.value("benchmarks", json::object());
  const json pb = prev.is_object() ? prev.value("benchmarks", json::object()) : json::object();
  const json rb = ref.is_object() ? ref.value("benchmarks", json::object()) : json::object();
  std::printf(
      "\nbenchmarks: median time per iteration (CPU; real for /real_time), ratios of the calibrated figure (>1 = "
      "slower)\n");
  std::printf("%-52s %10s %10s %6s %7s %7s %7s %7s  %s\n", "figure", "previous", "current", "noise", "cur/prev", "band",
              "cur/ref", "band", "verdict");
  for (const auto& [key, e] : cb.items()) {
    if (e.contains("error")) {
      std::printf("%-52s %s\n", key.c_str(), ("FAILED: " + e["error"].get<std::string>()).c_str());
      t.regressions.push_back(key + " failed");
      continue;
    }
    const double med = e.value("median", 0.0), pc = e.value("per_calibration", 0.0),
                 noise = e.value("noise_per_calibration", 0.0);
    // Display unit: ms above 1e6 ns, us above 1e3.
    const double scale = med >= 1e6 ? 1e-6 : med >= 1e3 ? 1e-3 : 1.0;
    const char* unit = med >= 1e6 ? "ms" : med >= 1e3 ? "us" : "ns";
    std::string prev_s = "-", rp = "-", bp = "-", rr = "-", br = "-";
    std::vector<std::string> verdicts;
    const std::string loaded = e.value("figure", std::string()) == "real_time" ? rules.too_loaded(e) : std::string();
    if (!loaded.empty()) {
      if (pb.contains(key)) prev_s = fmt(pb[key].value("median", 0.0) * scale) + unit;
      std::printf("%-52s %10s %10s %6s %7s %7s %7s %7s  %s\n", key.c_str(), prev_s.c_str(),
                  (fmt(med * scale) + unit).c_str(), pct(noise).c_str(), "-", "-", "-", "-", loaded.c_str());
      continue;
    }
    if (!rules.times_vs_previous && pb.contains(key)) {
      prev_s = fmt(pb[key].value("median", 0.0) * scale) + unit;
      verdicts.push_back("not judged: other machine");
    } else if (pb.contains(key) && num(pb[key], "per_calibration") && pc > 0) {
      const double ppc = pb[key]["per_calibration"].get<double>();
      prev_s = fmt(pb[key].value("median", 0.0) * scale) + unit;
      const double band = rules.band_of(noise, pb[key].value("noise_per_calibration", 0.0));
      const Verdict v = judge(pc, ppc, true, band);
      const double w = worse_by(pc, ppc, true);
      rp = ratio_str(pc / ppc), bp = pct(band);
      ++t.compared;
      if (v.regression) rules.flag_timing(key + " vs previous (x" + rp + ", band " + bp + ")", w, band);
      verdicts.push_back(v.text == "ok" ? "ok" : v.text + " vs prev" + rules.warn_suffix(v, w, band));
    } else if (!pb.empty()) {
      verdicts.push_back("new");
    }
    if (!rules.times_vs_reference && rb.contains(key)) {
      verdicts.push_back("not judged: other machine");
    } else if (rb.contains(key) && num(rb[key], "per_calibration") && pc > 0) {
      const double rpc = rb[key]["per_calibration"].get<double>();
      const double band = rules.band_of(noise, rb[key].value("noise", 0.0));
      const Verdict v = judge(pc, rpc, true, band);
      const double w = worse_by(pc, rpc, true);
      rr = ratio_str(pc / rpc), br = pct(band);
      ++t.compared;
      if (v.regression) rules.flag_timing(key + " vs reference (x" + rr + ", band " + br + ")", w, band);
      verdicts.push_back(v.text == "ok" ? "ok" : v.text + " vs ref" + rules.warn_suffix(v, w, band));
    }
    std::string verdict;
    for (const auto& v : verdicts) {
      if (v != "ok" && verdict.find(v) == std::string::npos) verdict += (verdict.empty() ? "" : ", ") + v;
    }
    if (verdict.empty()) verdict = verdicts.empty() ? "-" : "ok";
    std::printf("%-52s %10s %10s %6s %7s %7s %7s %7s  %s\n", key.c_str(), prev_s.c_str(),
                (fmt(med * scale) + unit).c_str(), pct(noise).c_str(), rp.c_str(), bp.c_str(), rr.c_str(), br.c_str(),
                verdict.c_str());
  }
  for (const auto& [key, e] : pb.items()) {
    if (!cb.contains(key)) {
      std::printf("%-52s missing in the current run (warning)\n", key.c_str());
      ++t.warnings;
    }
  }
  for (const auto& [key, e] : rb.items()) {
    if (!cb.contains(key) && !pb.contains(key)) {
      std::printf("%-52s in the reference, missing in the current run (warning)\n", key.c_str());
      ++t.warnings;
    }
  }
}

void compare_derived(const json& cur, const json& prev, const json& ref, const json& targets,
                     const TimingRules& rules) {
  Tally& t = rules.t;
  const json cd = cur.value("derived", json::object());
  const json pd = prev.is_object() ? prev.value("derived", json::object()) : json::object();
  const json rd = ref.is_object() ? ref.value("derived", json::object()) : json::object();
  std::printf("\nderived figures (speed-ups compared with previous/reference; absolute figures against targets)\n");
  std::printf("%-26s %10s %10s %6s %7s %7s %7s %7s %12s  %s\n", "figure", "previous", "current", "noise", "cur/prev",
              "band", "cur/ref", "band", "target", "verdict");
  for (const auto& [key, e] : cd.items()) {
    const double v = e.value("value", 0.0), cv = e.value("noise", 0.0);
    const bool lower = e.value("better", std::string("lower")) == "lower";
    const bool is_ratio = e.value("unit", std::string()) == "x";
    std::string ps = "-", rp = "-", bp = "-", rr = "-", br = "-", ts = "-";
    std::vector<std::string> verdicts;
    const std::string loaded = is_ratio ? rules.too_loaded(e) : std::string();
    if (!loaded.empty()) {
      if (pd.contains(key) && num(pd[key], "value")) ps = fmt(pd[key]["value"].get<double>());
      std::printf("%-26s %10s %10s %6s %7s %7s %7s %7s %12s  %s\n", key.c_str(), ps.c_str(), fmt(v).c_str(),
                  pct(cv).c_str(), "-", "-", "-", "-", "-", loaded.c_str());
      continue;
    }
    if (pd.contains(key) && num(pd[key], "value")) {
      const double pv = pd[key]["value"].get<double>();
      ps = fmt(pv);
      if (is_ratio && pv > 0 && v > 0) {
        const double band = rules.band_of(cv, pd[key].value("noise", 0.0));
        const Verdict vd = judge(v, pv, lower, band);
        const double w = worse_by(v, pv, lower);
        rp = ratio_str(v / pv), bp = pct(band);
        ++t.compared;
        if (vd.regression) rules.flag_timing(key + " vs previous (" + fmt(pv) + " -> " + fmt(v) + ")", w, band);
        if (vd.text != "ok") verdicts.push_back(vd.text + " vs prev" + rules.warn_suffix(vd, w, band));
      } else if (pv > 0) {
        rp = ratio_str(v / pv);
      }
    }
    if (is_ratio && rd.contains(key) && num(rd[key], "value") && v > 0) {
      const double rv = rd[key]["value"].get<double>();
      const double band = rules.band_of(cv, rd[key].value("noise", 0.0));
      const Verdict vd = judge(v, rv, lower, band);
      const double w = worse_by(v, rv, lower);
      rr = ratio_str(v / rv), br = pct(band);
      ++t.compared;
      if (vd.regression) rules.flag_timing(key + " vs reference (" + fmt(rv) + " -> " + fmt(v) + ")", w, band);
      if (vd.text != "ok") verdicts.push_back(vd.text + " vs ref" + rules.warn_suffix(vd, w, band));
    }
    if (targets.contains(key)) {
      const json& tg = targets[key];
      if (auto mn = num(tg, "min")) {
        ts = ">= " + fmt(*mn);
        if (v < *mn) verdicts.push_back("below target (warning)"), ++t.warnings;
      }
      if (auto mx = num(tg, "max")) {
        ts = "<= " + fmt(*mx);
        if (v > *mx) verdicts.push_back("below target (warning)"), ++t.warnings;
      }
      if (verdicts.empty()) verdicts.push_back("meets target");
    }
    std::string verdict;
    for (const auto& s : verdicts) verdict += (verdict.empty() ? "" : ", ") + s;
    if (verdict.empty()) verdict = "ok";
    std::printf("%-26s %10s %10s %6s %7s %7s %7s %7s %12s  %s\n", key.c_str(), ps.c_str(), fmt(v).c_str(),
                pct(cv).c_str(), rp.c_str(), bp.c_str(), rr.c_str(), br.c_str(), ts.c_str(), verdict.c_str());
  }
}

}  // namespace poise::nightly
