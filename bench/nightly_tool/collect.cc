// collect: one nightly run file from the raw outputs (calibration runs, Google Benchmark JSON,
// the studies' summary.json, bench/baselines/compare.py --json, load averages), with the derived
// figures (kDerived) computed from the benchmarks.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "nightly_common.h"
#include "nightly_modes.h"

namespace poise::nightly {

double to_ns(double t, const std::string& unit) {
  if (unit == "ns") return t;
  if (unit == "us") return t * 1e3;
  if (unit == "ms") return t * 1e6;
  if (unit == "s") return t * 1e9;
  throw InputError("unknown time_unit '" + unit + "'");
}

// Google Benchmark JSON -> per run name: times (ns) by repetition, items/s, errors.
struct BenchRuns {
  std::vector<std::string> order;
  std::map<std::string, std::map<int, double>> real_ns;  // run name -> repetition -> ns (the figure)
  std::map<std::string, std::string> figure;             // "real_time" or "cpu_time"
  std::map<std::string, std::vector<double>> items_per_s;
  std::map<std::string, std::string> error;
  std::map<std::string, std::pair<int, int>> rank;  // (family_index, instance): definition order
};

BenchRuns read_bench(const std::string& path) {
  const json j = read_json(path);
  if (!j.contains("benchmarks") || !j["benchmarks"].is_array()) throw InputError(path + ": no 'benchmarks' array");
  BenchRuns b;
  for (const auto& e : j["benchmarks"]) {
    if (e.value("run_type", std::string("iteration")) != "iteration") continue;
    const std::string name = e.value("run_name", e.value("name", std::string()));
    if (name.empty()) throw InputError(path + ": benchmark without a name");
    if (!b.real_ns.count(name) && !b.error.count(name)) b.order.push_back(name);
    b.rank[name] = {e.value("family_index", 0), e.value("per_family_instance_index", 0)};
    if (e.value("error_occurred", false)) {
      b.error[name] = e.value("error_message", std::string("error"));
      continue;
    }
    const int rep = e.value("repetition_index", static_cast<int>(b.real_ns[name].size()));
    // The figure: real time for multi-threaded runs (UseRealTime: the name ends in /real_time),
    // else CPU time (items_per_second is computed from it), which does not count the time spent
    // waiting for a core when a neighbour is busy.
    const bool real = name.size() >= 10 && name.compare(name.size() - 10, 10, "/real_time") == 0;
    b.figure[name] = real ? "real_time" : "cpu_time";
    b.real_ns[name][rep] =
        to_ns(e.at(real ? "real_time" : "cpu_time").get<double>(), e.value("time_unit", std::string("ns")));
    if (e.contains("items_per_second")) b.items_per_s[name].push_back(e["items_per_second"].get<double>());
  }
  // Random interleaving shuffles the entries: back to the order the benchmarks are defined in.
  std::stable_sort(b.order.begin(), b.order.end(),
                   [&](const std::string& x, const std::string& y) { return b.rank[x] < b.rank[y]; });
  return b;
}

std::vector<double> values_of(const std::map<int, double>& m) {
  std::vector<double> v;
  for (const auto& [rep, x] : m) v.push_back(x);
  return v;
}

// Derived figures: the README's targets and the thread scaling, from the benchmarks.
struct DerivedDef {
  const char* name;
  const char* description;
  const char* bench;      // binary/run name of the numerator
  const char* per_bench;  // for ratios: the denominator (speed-up = time(per) / time(bench))
  const char* kind;       // "items_per_s", "time_ms", "speedup"
  const char* better;     // "higher" | "lower"
};

constexpr std::array<DerivedDef, 5> kDerived{{
    {"los_evals_per_s_per_core", "gimbal-angle LOS evaluations/s on one core (realistic error states)",
     "poise_bench/BM_LosGridEvaluation/states:256", nullptr, "items_per_s", "higher"},
    {"los_study_speedup_2t", "LOS study run, samples/s on 2 threads over 1 thread",
     "poise_bench/BM_StudyRun/threads:2/real_time", "poise_bench/BM_StudyRun/threads:1/real_time", "speedup", "higher"},
    {"los_compute_speedup_2t", "parallel part of the LOS run alone, 2 threads over 1 (diagnostic)",
     "poise_bench/BM_StudyComputeOnly/threads:2/real_time", "poise_bench/BM_StudyComputeOnly/threads:1/real_time",
     "speedup", "higher"},
    {"balancing_run_ms", "one complete balancing run, one core (ms)", "poise_balancing_bench/BM_BalancingRun", nullptr,
     "time_ms", "lower"},
    {"gimbal_measurement36_ms", "one simulated 36-point gimbal measurement at 500 Hz, one core (ms)",
     "poise_gimbal_bench/BM_Measurement36/rate:500", nullptr, "time_ms", "lower"},
}};

// A figures file of another program as it goes into the run file: {"status": "ran", ...the
// file...} when it has `schema` (and, if given, the object `required`), else what bench/nightly
// wrote instead ({"status": "not run", "reason"}), or "not run" with the reason it cannot be
// read: the rest of the run is kept. Used for the baselines (bench/baselines/compare.py --json,
// poise-baselines/1, its "ratios") and the LOS run at scale (bench/los_scale --json,
// poise-los-scale/1, whose own "status" is its exit status: kept as "exit_status").
json embedded_entry(const std::string& path, const std::string& schema, const char* required) {
  json j;
  try {
    j = read_json(path);
  } catch (const InputError& e) {
    return json{{"status", "not run"}, {"reason", e.what()}};
  }
  if (j.is_object() && j.value("schema", std::string()) == schema &&
      (required == nullptr || (j.contains(required) && j[required].is_object()))) {
    json e = j;
    if (j.contains("status")) e["exit_status"] = j["status"];
    e["status"] = "ran";
    return e;
  }
  if (j.is_object() && j.value("status", std::string()) == "not run") return j;
  return json{{"status", "not run"},
              {"reason", path + ": neither a " + schema + " file" +
                             (required ? std::string(" with '") + required + "'" : std::string()) +
                             " nor {\"status\": \"not run\"}"}};
}

int run_collect(const std::vector<std::string>& args) {
  std::string out, meta_path;
  std::vector<std::string> cal_paths;
  struct BenchArg {
    std::string binary;
    int rc;
    std::string path;
  };
  struct StudyArg {
    std::string name;
    int rc;
    double wall;
    std::string path;
  };
  std::vector<BenchArg> benches;
  std::vector<StudyArg> studies;
  std::map<std::string, std::pair<std::string, std::string>> study_references;  // name -> file, verdict
  std::string baselines_path, scale_path;
  std::map<std::string, std::pair<double, double>> loads;  // name -> load average before, after
  auto need = [&](std::size_t i, std::size_t n, const std::string& opt) {
    if (i + n >= args.size()) throw InputError("collect: " + opt + " needs " + std::to_string(n) + " values");
  };
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--out")
      need(i, 1, a), out = args[++i];
    else if (a == "--meta")
      need(i, 1, a), meta_path = args[++i];
    else if (a == "--calibration")
      need(i, 1, a), cal_paths.push_back(args[++i]);
    else if (a == "--bench") {
      need(i, 3, a);
      benches.push_back({args[i + 1], static_cast<int>(parse_double(args[i + 2], a)), args[i + 3]});
      i += 3;
    } else if (a == "--study") {
      need(i, 4, a);
      studies.push_back(
          {args[i + 1], static_cast<int>(parse_double(args[i + 2], a)), parse_double(args[i + 3], a), args[i + 4]});
      i += 4;
    } else if (a == "--study-reference") {  // NAME FILE VERDICT: samples against the recorded reference
      need(i, 3, a);
      study_references[args[i + 1]] = {args[i + 2], args[i + 3]};
      i += 3;
    } else if (a == "--load") {  // the 1-minute load average before and after a binary or study
      need(i, 3, a);
      loads[args[i + 1]] = {parse_double(args[i + 2], a), parse_double(args[i + 3], a)};
      i += 3;
    } else if (a == "--baselines")
      need(i, 1, a), baselines_path = args[++i];
    else if (a == "--scale")
      need(i, 1, a), scale_path = args[++i];
    else
      throw InputError("collect: unknown argument '" + a + "'");
  }
  if (out.empty() || meta_path.empty()) throw InputError("collect: --out and --meta are required");

  json doc = read_json(meta_path);
  doc["schema"] = "poise-nightly/1";

  // Calibration: every repetition of every calibration run, pooled (the machine's speed), and
  // per benchmark binary the runs just before and just after it (when there is one before each
  // binary and one after the last): the load of a shared machine drifts over a nightly, and the
  // binary's figures are divided by the calibration of their own time.
  std::vector<double> cal;
  std::vector<std::vector<double>> cal_runs;
  for (const auto& p : cal_paths) {
    const json c = read_json(p);
    cal_runs.emplace_back();
    for (const auto& v : c.at("values")) cal.push_back(v.get<double>()), cal_runs.back().push_back(v.get<double>());
  }
  const Spread cs = spread_of(cal);
  const bool local_cal = cal_runs.size() == benches.size() + 1;
  json cj = {{"description",
              "fixed libm/floating-point workload (poise_nightly_compare calibrate), ns per step (CPU "
              "time), run before and between the benchmark binaries; all runs pooled"},
             {"unit", "ns"}};
  cj.update(spread_json(cs, cal));
  doc["calibration"] = cj;

  json binaries = json::object(), bj = json::object();
  std::map<std::string, std::map<int, double>> all_real;
  std::map<std::string, Spread> all_items;
  for (std::size_t bi = 0; bi < benches.size(); ++bi) {
    const BenchArg& b = benches[bi];
    json status = {{"exit_status", b.rc}};
    std::vector<double> lv = cal;  // this binary's calibration
    if (local_cal) {
      lv = cal_runs[bi];
      lv.insert(lv.end(), cal_runs[bi + 1].begin(), cal_runs[bi + 1].end());
    }
    const Spread ls = spread_of(lv);
    status["calibration"] = {{"scope", local_cal ? "the calibration runs before and after this binary" : "all"},
                             {"median", ls.median},
                             {"noise", ls.noise},
                             {"values", lv}};
    BenchRuns runs;
    try {
      runs = read_bench(b.path);
    } catch (const InputError& e) {
      status["error"] = e.what();
      binaries[b.binary] = status;
      continue;
    }
    if (loads.count(b.binary)) {
      status["load_avg_before"] = loads[b.binary].first;
      status["load_avg_after"] = loads[b.binary].second;
    }
    binaries[b.binary] = status;
    for (const auto& name : runs.order) {
      const std::string key = b.binary + "/" + name;
      json e = {{"binary", b.binary}, {"name", name}};
      // The load beside the figure: the higher of the binary's before and after.
      if (loads.count(b.binary)) e["load_avg"] = std::max(loads[b.binary].first, loads[b.binary].second);
      if (runs.error.count(name)) {
        e["error"] = runs.error[name];
        bj[key] = e;
        continue;
      }
      const std::vector<double> v = values_of(runs.real_ns[name]);
      const Spread s = spread_of(v);
      e["figure"] = runs.figure[name];
      e["unit"] = "ns";
      e["better"] = "lower";
      e.update(spread_json(s, v));
      if (ls.median > 0) e["per_calibration"] = s.median / ls.median;
      e["noise_per_calibration"] = std::hypot(s.noise, ls.noise);  // noise of per_calibration
      if (runs.items_per_s.count(name)) {
        const Spread is = spread_of(runs.items_per_s[name]);
        e["items_per_second"] = {{"median", is.median}, {"min", is.min}, {"max", is.max}, {"cv", is.cv}};
        all_items[key] = is;
      }
      all_real[key] = runs.real_ns[name];
      bj[key] = e;
    }
  }
  doc["binaries"] = binaries;
  doc["benchmarks"] = bj;

  json dj = json::object();
  for (const auto& d : kDerived) {
    json e = {{"description", d.description}, {"from", d.bench}, {"better", d.better}};
    const std::string kind = d.kind;
    if (kind == "items_per_s") {
      if (!all_items.count(d.bench)) continue;
      const Spread& s = all_items[d.bench];
      e.update(
          json{{"unit", "1/s"}, {"value", s.median}, {"min", s.min}, {"max", s.max}, {"cv", s.cv}, {"noise", s.noise}});
    } else if (kind == "time_ms") {
      if (!all_real.count(d.bench)) continue;
      const Spread s = spread_of(values_of(all_real[d.bench]));
      e.update(json{{"unit", "ms"},
                    {"value", s.median * 1e-6},
                    {"min", s.min * 1e-6},
                    {"max", s.max * 1e-6},
                    {"cv", s.cv},
                    {"noise", s.noise}});
    } else {  // speed-up: median time on 1 thread over median time on 2 (repetitions are interleaved
              // at random, so they are not paired); noise: both medians' combined
      if (!all_real.count(d.bench) || !all_real.count(d.per_bench)) continue;
      const Spread fast = spread_of(values_of(all_real[d.bench]));
      const Spread slow = spread_of(values_of(all_real[d.per_bench]));
      if (fast.median <= 0) continue;
      e["per"] = d.per_bench;
      e.update(json{{"unit", "x"},
                    {"value", slow.median / fast.median},
                    {"cv", std::hypot(slow.cv, fast.cv)},
                    {"noise", std::hypot(slow.noise, fast.noise)}});
    }
    const std::string from = d.bench, binary = from.substr(0, from.find('/'));
    if (loads.count(binary)) e["load_avg"] = std::max(loads[binary].first, loads[binary].second);
    dj[d.name] = e;
  }
  doc["derived"] = dj;

  json sj = json::object();
  for (const auto& st : studies) {
    json e = {{"exit_status", st.rc}, {"wall_s", st.wall}};
    if (loads.count("study:" + st.name)) {
      e["load_avg"] = std::max(loads["study:" + st.name].first, loads["study:" + st.name].second);
    }
    if (study_references.count(st.name)) {
      const auto& [file, verdict] = study_references[st.name];
      e["reference"] = {{"file", file}, {"verdict", verdict}};
    }
    json summary;
    try {
      summary = read_json(st.path);
    } catch (const InputError& err) {
      e["error"] = err.what();
      sj[st.name] = e;
      continue;
    }
    const json prov = summary.value("provenance", json::object());
    e["samples"] = prov.value("samples", json());
    e["seed"] = prov.value("seed", json());
    e["threads"] = prov.value("threads", json());
    e["run_wall_time_s"] = prov.value("wall_time_s", json());  // as the study reports it
    e["study_file_sha1"] = prov.value("study_file_sha1", json());
    e["model_file_sha1"] = prov.value("model_file_sha1", json());
    e["failures"] = summary.contains("failures") ? summary["failures"].value("count", json()) : json();
    json stats = json::object();
    const json summary_outputs = summary.value("outputs", json::object());
    for (const auto& [out_name, o] : summary_outputs.items()) {
      json s = json::object();
      for (const char* k : {"mean", "std", "p50", "p95", "p99_73", "max"}) {
        if (!o.contains(k) || !o[k].is_object()) continue;
        s[k] = o[k].value("value", json());
        // The 95 % interval's ends (null where one-sided), compared like the values.
        const json ci = o[k].value("ci95", json());
        if (ci.is_array() && ci.size() == 2) {
          s[std::string(k) + "_lo"] = ci[0];
          s[std::string(k) + "_hi"] = ci[1];
        }
      }
      if (o.contains("n")) s["n"] = o["n"];
      stats[out_name] = s;
    }
    e["statistics"] = stats;
    sj[st.name] = e;
  }
  doc["studies"] = sj;
  if (!baselines_path.empty()) doc["baselines"] = embedded_entry(baselines_path, "poise-baselines/1", "ratios");
  if (!scale_path.empty()) doc["scale"] = embedded_entry(scale_path, "poise-los-scale/1", nullptr);
  write_json(out, doc);
  return kExitOk;
}

}  // namespace poise::nightly
