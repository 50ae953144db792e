// compare (the default mode): reads the runs and the reference, prints the report's header,
// the calibration and the failed binaries, runs the sections (compare_figures.cc,
// compare_baselines.cc, compare_studies.cc) and gives the verdict and the exit status.
#include "compare.h"

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "nightly_modes.h"

namespace poise::nightly {

double worse_by(double cur, double other, bool lower_better) {
  return lower_better ? cur / other - 1.0 : other / cur - 1.0;
}

Verdict judge(double cur, double other, bool lower_better, double band) {
  const double w = worse_by(cur, other, lower_better);
  if (w > band) return {"REGRESSION", true};
  if (-w / (1.0 + w) > band) return {"better", false};  // improvement beyond the band
  return {"ok", false};
}

std::string describe(const json& run, const std::string& path) {
  std::ostringstream os;
  os << path << " (" << run.value("date", std::string("?"));
  if (run.contains("git"))
    os << ", " << run["git"].value("commit", std::string("?")).substr(0, 12)
       << (run["git"].value("dirty", false) ? "-dirty" : "");
  if (run.contains("machine"))
    os << ", " << run["machine"].value("nproc", 0) << " x " << run["machine"].value("cpu_model", std::string("?"));
  if (run.contains("settings")) {
    os << ", " << run["settings"].value("repetitions", 0) << " repetitions";
    if (run["settings"].value("quick", false)) os << ", quick";
  }
  os << ")";
  return os.str();
}

std::string machine_key(const json& run) {
  const json m = run.contains("machine")                                        ? run["machine"]
                 : run.contains("source_run") && run["source_run"].contains("machine") ? run["source_run"]["machine"]
                                                                                : json();
  if (!m.is_object()) return "";
  const std::string host = m.value("hostname", std::string()), cpu = m.value("cpu_model", std::string());
  if (host.empty() && cpu.empty()) return "";
  return host + " | " + cpu + " | " + std::to_string(m.value("nproc", 0)) + " cores";
}

int run_machine_key(const std::vector<std::string>& args) {
  if (args.size() != 1) throw InputError("machine-key: one RUN.json expected");
  std::printf("%s\n", machine_key(read_json(args[0])).c_str());
  return kExitOk;
}

namespace {

// Which absolute times are judged (TimingRules::times_vs_*), said once above the tables.
void decide_machines(const json& cur, const json& prev, const json& ref, TimingRules& rules) {
  const std::string here = machine_key(cur);
  std::printf("  machine:   %s\n", here.empty() ? "(not recorded)" : here.c_str());
  if (!prev.is_null()) rules.times_vs_previous = !here.empty() && machine_key(prev) == here;
  if (!ref.is_null()) rules.times_vs_reference = !here.empty() && machine_key(ref) == here;
  if (!prev.is_null() && !rules.times_vs_previous)
    std::printf("note: the previous run was recorded on another machine (%s): its times are not judged here.\n",
                machine_key(prev).empty() ? "not recorded" : machine_key(prev).c_str());
  if (!ref.is_null() && !rules.times_vs_reference)
    std::printf(
        "note: the reference was recorded on another machine (%s): its benchmark times are not judged here; its "
        "ratios are, and the studies against their recorded references.\n",
        machine_key(ref).empty() ? "not recorded" : machine_key(ref).c_str());
  const bool has_own_times = (!prev.is_null() && rules.times_vs_previous) || (!ref.is_null() && rules.times_vs_reference);
  if (!has_own_times)
    std::printf(
        "note: first run on this machine: its times are this machine's baseline (judged from its next run on); "
        "ratios, memory and the studies' samples are judged now.\n");
}

}  // namespace

int run_compare(const std::vector<std::string>& args) {
  std::string cur_path, prev_path, ref_path;
  Options opt;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= args.size()) throw InputError(a + " needs a value");
      return args[++i];
    };
    if (a == "--previous")
      prev_path = value();
    else if (a == "--reference")
      ref_path = value();
    else if (a == "--k")
      opt.k = parse_double(value(), a);
    else if (a == "--floor")
      opt.floor = parse_double(value(), a);
    else if (a == "--wall-warn")
      opt.wall_warn = parse_double(value(), a);
    else if (a == "--ratio-band")
      opt.ratio_band = parse_double(value(), a);
    else if (a == "--all")
      opt.all = true;
    else if (a == "--warn-timing")
      opt.warn_timing = true;
    else if (a == "--gross")
      opt.gross = parse_double(value(), a);
    else if (a == "--idle-margin")
      opt.idle_margin = parse_double(value(), a);
    else if (a == "--memory-band")
      opt.memory_band = parse_double(value(), a);
    else if (a.rfind("--", 0) == 0)
      throw InputError("unknown option '" + a + "' (see --help)");
    else if (cur_path.empty())
      cur_path = a;
    else
      throw InputError("more than one CURRENT.json given ('" + a + "')");
  }
  if (cur_path.empty()) throw InputError("no CURRENT.json given (see --help)");
  if (!(opt.ratio_band > 0)) throw InputError("--ratio-band must be > 0 (a relative band, e.g. 0.2)");
  const json cur = read_json(cur_path);
  if (cur.value("schema", std::string()) != "poise-nightly/1")
    throw InputError(cur_path + ": not a nightly run (schema poise-nightly/1 expected)");
  json prev, ref;
  if (!prev_path.empty()) {
    prev = read_json(prev_path);
    if (prev.value("schema", std::string()) != "poise-nightly/1")
      throw InputError(prev_path + ": not a nightly run (schema poise-nightly/1 expected)");
  }
  if (!ref_path.empty()) {
    ref = read_json(ref_path);
    if (ref.value("schema", std::string()) != "poise-nightly-reference/1")
      throw InputError(ref_path + ": not a nightly reference (schema poise-nightly-reference/1 expected)");
  }
  const json targets = ref.is_object() && ref.contains("targets") ? ref["targets"] : default_targets();

  Tally t;
  const int cores = cur.contains("machine") ? cur["machine"].value("nproc", 0) : 0;
  TimingRules rules{opt, t, cores};
  std::printf("poise nightly compare\n  current:   %s\n", describe(cur, cur_path).c_str());
  std::printf("  previous:  %s\n", prev.is_null() ? "(none)" : describe(prev, prev_path).c_str());
  std::printf("  reference: %s\n", ref.is_null() ? "(none)" : ref_path.c_str());
  std::printf(
      "rule: a figure regresses when worse than the previous run or the reference by more than\n"
      "  band = max(%s, %.3g x sqrt(noise_current^2 + noise_other^2)). Benchmark figure: median time per\n"
      "  iteration (CPU; real for /real_time) / calibration median; noise: relative standard error of the\n"
      "  median(s), 1.2533 sd / sqrt(n) / median x t(0.975, n-1) / 1.96. Study samples must equal their\n"
      "  recorded reference (tests/data/study_reference/). Targets and study wall times only warn.%s\n",
      pct(opt.floor).c_str(), opt.k,
      opt.warn_timing ? "\n  --warn-timing (quick run): timing regressions only warn too." : "");

  decide_machines(cur, prev, ref, rules);

  // Calibration itself (informative: the machine's speed).
  const json cal = cur.value("calibration", json::object());
  std::printf("\ncalibration: median %s ns/step, cv %s, spread %s (n %d)", fmt(cal.value("median", 0.0)).c_str(),
              pct(cal.value("cv", 0.0)).c_str(), pct(cal.value("spread", 0.0)).c_str(), cal.value("n", 0));
  if (!prev.is_null() && rules.times_vs_previous && num(prev.value("calibration", json::object()), "median"))
    std::printf("; previous %s ns/step (machine speed ratio %s)",
                fmt(prev["calibration"]["median"].get<double>()).c_str(),
                ratio_str(cal.value("median", 0.0) / prev["calibration"]["median"].get<double>()).c_str());
  std::printf("\n");

  // Failed binaries / benchmarks.
  const json cur_binaries = cur.value("binaries", json::object());
  for (const auto& [bin, st] : cur_binaries.items()) {
    if (st.value("exit_status", 0) != 0 || st.contains("error")) {
      std::printf("FAILED: benchmark binary %s (exit status %d%s%s)\n", bin.c_str(), st.value("exit_status", 0),
                  st.contains("error") ? ": " : "", st.value("error", std::string()).c_str());
      t.regressions.push_back("binary " + bin + " failed");
    }
  }

  compare_benchmarks(cur, prev, ref, rules);
  compare_derived(cur, prev, ref, targets, rules);
  compare_baselines(cur, prev, ref, opt, t);
  compare_scale(cur, prev, rules);
  compare_studies(cur, prev, ref, rules);

  std::printf("\n%d figures compared, %d not judged (load), %d warnings, %zu regressions\n", t.compared, t.not_judged,
              t.warnings, t.regressions.size());
  if (t.compared == 0 && prev.is_null() && ref.is_null())
    std::printf("note: nothing to compare with (no previous run, no reference)\n");
  if (!t.regressions.empty()) {
    std::printf("verdict: REGRESSION (exit 3):\n");
    for (const auto& r : t.regressions) std::printf("  - %s\n", r.c_str());
    return kExitRegression;
  }
  std::printf("verdict: OK (exit 0)\n");
  return kExitOk;
}

}  // namespace poise::nightly
