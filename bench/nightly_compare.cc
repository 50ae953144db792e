/// poise_nightly_compare: the JSON side of bench/nightly (issue 9 item 7). Four modes:
///
///   poise_nightly_compare CURRENT.json [--previous PREV.json] [--reference REF.json]
///                         [--k K] [--floor F] [--stat-rtol R] [--all]
///       compare a nightly run with the previous run and with the stored reference figures;
///       prints a table; exit 0 fine, 3 regression, 2 bad input.
///   poise_nightly_compare calibrate [--repetitions N] [--min-time S]
///       time the fixed calibration workload; prints {"values": [ns per step, ...]}.
///   poise_nightly_compare collect --out FILE --meta META.json [--calibration CAL.json]...
///                         [--bench BINARY RC BENCH.json]... [--study NAME RC WALL_S SUMMARY.json]...
///                         [--baselines BASELINES.json] [--load NAME BEFORE AFTER]...
///       assemble one nightly file from the raw outputs (Google Benchmark JSON, summary.json,
///       bench/baselines/compare.py --json).
///   poise_nightly_compare make-reference CURRENT.json --out REF.json [--old OLD_REF.json]
///       write the reference figures from a run (targets kept from OLD_REF.json if given).
///
/// The rule (also in bench/NIGHTLY.md): a timing figure is a benchmark's median time per iteration
/// (CPU time; real time for the multi-threaded /real_time runs) divided by the calibration
/// workload's median CPU time in the calibration runs just before and after its program (same
/// machine, same time: a slower or faster machine cancels out). The noise of a median over n
/// repetitions is its relative standard error, 1.2533 sd / sqrt(n) / median, widened by
/// t(0.975, n - 1) / 1.96 since sd is estimated from n values (x1.42 for n = 5); a calibrated
/// figure's noise combines the benchmark's and the calibration's, sqrt(noise_bench^2 +
/// noise_calibration^2). A figure regresses when it is worse than the previous run's (or the
/// reference's) by more than
/// band = max(floor, k * sqrt(noise_current^2 + noise_other^2)), k = 3, floor = 5 %.
/// The 2-thread speed-ups are ratios already (no calibration) and follow the same rule. Multi-
/// threaded figures (real-time benchmarks, speed-ups) are judged only when the load average beside
/// them (bench/nightly records it before and after each binary) is below (cores - 1) + 0.5: on a
/// loaded machine they measure the neighbours. With --warn-timing (quick runs) a timing regression
/// only warns unless worse by more than max(2 x band, 50 %).
/// Reference-study statistics (fixed seed and sample count, deterministic), their values and their
/// 95 % interval ends, must equal the reference to a relative 1e-9. Absolute targets (README) are checked and only warned about.
/// Study wall times (one run each, no noise estimate) are warned about beyond 25 %.
/// Baseline ratios (NumPy/SciPy CPU time over Poise's, same run): a warning below their target, a
/// regression below the previous run's or the reference's ratio / (1 + ratio_band), ratio_band 0.2.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using json = nlohmann::ordered_json;

constexpr int kExitOk = 0;
constexpr int kExitInput = 2;
constexpr int kExitRegression = 3;

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

json read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot open " + path);
  try {
    return json::parse(in);
  } catch (const json::parse_error& e) {
    throw InputError(path + ": not valid JSON: " + e.what());
  }
}

void write_json(const std::string& path, const json& j) {
  std::ofstream out(path);
  if (!out) throw InputError("cannot write " + path);
  out << j.dump(2) << '\n';
  if (!out) throw InputError("error writing " + path);
}

double parse_double(const std::string& s, const std::string& what) {
  try {
    std::size_t pos = 0;
    const double v = std::stod(s, &pos);
    if (pos != s.size() || !std::isfinite(v)) throw std::invalid_argument(s);
    return v;
  } catch (const std::exception&) {
    throw InputError(what + ": not a number: '" + s + "'");
  }
}

// ---------------------------------------------------------------------------------------------
// Statistics over repetitions.

struct Spread {
  std::size_t n = 0;
  double median = 0, min = 0, max = 0, mean = 0, cv = 0, spread = 0;
  // Relative standard error of the median, 1.2533 sd / sqrt(n) / median (the median of n normal
  // draws), times t(0.975, n - 1) / 1.96: the sd is itself estimated from n draws (x1.42 for
  // n = 5, x6.5 for n = 2). The sample sd: one disturbed repetition widens it (conservative).
  double noise = 0;
};

// Student-t 97.5 % quantile over the normal one, for n - 1 degrees of freedom.
double t_factor(std::size_t n) {
  static constexpr std::array<double, 11> t{0, 12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228};
  const std::size_t dof = n > 0 ? n - 1 : 0;
  if (dof == 0) return 1.0;
  const double q = dof < t.size() ? t[dof] : dof < 20 ? 2.131 : dof < 30 ? 2.086 : 2.042;
  return q / 1.96;
}

Spread spread_of(std::vector<double> v) {
  Spread s;
  s.n = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.min = v.front(), s.max = v.back();
  s.median = v.size() % 2 == 1 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  double sum = 0;
  for (double x : v) sum += x;
  s.mean = sum / static_cast<double>(v.size());
  double ss = 0;
  for (double x : v) ss += (x - s.mean) * (x - s.mean);
  const double sd = v.size() > 1 ? std::sqrt(ss / static_cast<double>(v.size() - 1)) : 0.0;
  s.cv = s.mean != 0 ? sd / std::abs(s.mean) : 0.0;
  s.spread = s.median != 0 ? (s.max - s.min) / std::abs(s.median) : 0.0;
  s.noise = s.median != 0
                ? t_factor(v.size()) * 1.2533 * sd / std::sqrt(static_cast<double>(v.size())) / std::abs(s.median)
                : 0.0;
  return s;
}

json spread_json(const Spread& s, const std::vector<double>& values) {
  return json{{"median", s.median}, {"min", s.min},     {"max", s.max}, {"mean", s.mean},  {"cv", s.cv},
              {"spread", s.spread}, {"noise", s.noise}, {"n", s.n},     {"values", values}};
}

// ---------------------------------------------------------------------------------------------
// calibrate: a fixed, machine-bound workload (libm, dependent floating-point chain, table
// look-ups in L1) of the same character as the engine's inner loops, with no project code:
// the unit that timings are divided by.

double calibration_kernel(std::size_t steps, std::array<double, 4096>& table) {
  double a = 0.3, b = 0.7, acc = 0.0;
  std::uint32_t idx = 1;
  for (std::size_t i = 0; i < steps; ++i) {
    const double s = std::sin(a), c = std::cos(b);
    const double r = std::sqrt(a * a + b * b + 1.0);
    a = 0.5 * a + 0.3 * c + 1e-3 * table[idx];
    b = 0.5 * b + 0.3 * s + 0.1 / r;
    idx = (idx * 1103515245u + 12345u) & 4095u;
    table[idx] += 1e-9 * a;
    acc += a * b;
  }
  return acc;
}

int run_calibrate(const std::vector<std::string>& args) {
  int reps = 5;
  double min_time = 0.2;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--repetitions" && i + 1 < args.size()) {
      reps = static_cast<int>(parse_double(args[++i], "--repetitions"));
    } else if (args[i] == "--min-time" && i + 1 < args.size()) {
      min_time = parse_double(args[++i], "--min-time");
    } else {
      throw InputError("calibrate: unknown argument '" + args[i] + "'");
    }
  }
  if (reps < 1 || min_time <= 0) throw InputError("calibrate: --repetitions >= 1 and --min-time > 0");
  std::array<double, 4096> table{};
  for (std::size_t i = 0; i < table.size(); ++i) table[i] = static_cast<double>(i % 97) / 97.0;
  volatile double sink = 0;
  auto time_steps = [&](std::size_t steps) {
    const std::clock_t t0 = std::clock();  // process CPU time: a busy neighbour does not count
    sink = sink + calibration_kernel(steps, table);
    return static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC;
  };
  std::size_t steps = 1 << 14;  // grow until one repetition lasts min_time (also warms up)
  for (double t = time_steps(steps); t < min_time; t = time_steps(steps)) {
    const double f = t > 0 ? std::clamp(1.3 * min_time / t, 1.5, 16.0) : 16.0;
    steps = static_cast<std::size_t>(static_cast<double>(steps) * f);
  }
  std::vector<double> values;
  for (int r = 0; r < reps; ++r) values.push_back(time_steps(steps) / static_cast<double>(steps) * 1e9);
  std::cout << json{{"name", "calibration"}, {"unit", "ns"}, {"steps", steps}, {"values", values}}.dump() << '\n';
  return kExitOk;
}

// ---------------------------------------------------------------------------------------------
// collect

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

json default_targets() {
  return json{
      {"los_evals_per_s_per_core", {{"min", 10e6}, {"source", "README: >= 10 M LOS evaluations/s per core"}}},
      {"los_study_speedup_2t", {{"min", 1.85}, {"source", "issue 19: >= 1.85x from 1 to 2 threads for a whole LOS run"}}},
      {"balancing_run_ms", {{"max", 5.0}, {"source", "README: one balancing run <= 5 ms per core"}}},
      {"gimbal_measurement36_ms", {{"max", 50.0}, {"source", "bench/gimbal_bench.cc: <= 50 ms per measurement"}}},
  };
}

// The baselines' figures (bench/baselines/compare.py --json, schema poise-baselines/1) as they go
// into the run file: {"status": "ran", ...the file...}, or {"status": "not run", "reason"} when
// bench/nightly wrote that instead or the file cannot be read: the rest of the run is kept.
json baselines_entry(const std::string& path) {
  json j;
  try {
    j = read_json(path);
  } catch (const InputError& e) {
    return json{{"status", "not run"}, {"reason", e.what()}};
  }
  if (j.is_object() && j.value("schema", std::string()) == "poise-baselines/1" && j.contains("ratios") &&
      j["ratios"].is_object()) {
    json e = {{"status", "ran"}};
    e.update(j);
    return e;
  }
  if (j.is_object() && j.value("status", std::string()) == "not run") return j;
  return json{{"status", "not run"},
              {"reason", path + ": neither a poise-baselines/1 file with 'ratios' nor {\"status\": \"not run\"}"}};
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
  std::string baselines_path;
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
    } else if (a == "--load") {  // the 1-minute load average before and after a binary or study
      need(i, 3, a);
      loads[args[i + 1]] = {parse_double(args[i + 2], a), parse_double(args[i + 3], a)};
      i += 3;
    } else if (a == "--baselines")
      need(i, 1, a), baselines_path = args[++i];
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
  if (!baselines_path.empty()) doc["baselines"] = baselines_entry(baselines_path);
  write_json(out, doc);
  return kExitOk;
}

// ---------------------------------------------------------------------------------------------
// make-reference

int run_make_reference(const std::vector<std::string>& args) {
  std::string current, out, old;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--out" && i + 1 < args.size())
      out = args[++i];
    else if (args[i] == "--old" && i + 1 < args.size())
      old = args[++i];
    else if (current.empty() && args[i].rfind("--", 0) != 0)
      current = args[i];
    else
      throw InputError("make-reference: unknown argument '" + args[i] + "'");
  }
  if (current.empty() || out.empty()) throw InputError("make-reference: CURRENT.json and --out REF.json needed");
  const json run = read_json(current);
  json targets = default_targets();
  json o;
  if (!old.empty()) {
    o = read_json(old);
    if (o.contains("targets")) targets = o["targets"];
  }
  json ref = {{"schema", "poise-nightly-reference/1"},
              {"note",
               "Written by bench/nightly --update-reference; the figures of the run below. Study "
               "statistics must match to a tight relative tolerance; benchmark figures are times "
               "relative to the calibration workload with their noise. Targets are warn-only."},
              {"source_run",
               {{"date", run.value("date", json())},
                {"git", run.value("git", json())},
                {"machine", run.value("machine", json())},
                {"settings", run.value("settings", json())}}},
              {"targets", targets}};
  json b = json::object();
  const json run_benchmarks = run.value("benchmarks", json::object());
  for (const auto& [key, e] : run_benchmarks.items()) {
    if (!e.contains("per_calibration")) continue;
    b[key] = {{"per_calibration", e["per_calibration"]},
              {"noise", e.value("noise_per_calibration", 0.0)},
              {"median_ns", e.value("median", 0.0)}};
  }
  ref["benchmarks"] = b;
  json d = json::object();
  const json run_derived = run.value("derived", json::object());
  for (const auto& [key, e] : run_derived.items()) {
    d[key] = {{"value", e.value("value", 0.0)}, {"noise", e.value("noise", 0.0)}, {"unit", e.value("unit", "")}};
  }
  ref["derived"] = d;
  // Baseline ratios: from this run when its baselines ran, else kept from the old reference.
  const json run_baselines = run.value("baselines", json::object());
  if (run_baselines.value("status", std::string()) == "ran") {
    json rb = {{"source", "bench/baselines/compare.py in the source run"},
               {"quick", run_baselines.value("quick", json())},
               {"samples", run_baselines.value("samples", json())},
               {"load_avg_start", run_baselines.value("load_avg_start", json())},
               {"load_avg_end", run_baselines.value("load_avg_end", json())}};
    json ratios = json::object();
    const json run_ratios = run_baselines.value("ratios", json::object());  // named: items() keeps a reference
    for (const auto& [key, e] : run_ratios.items()) {
      if (!e.contains("value") || !e["value"].is_number()) continue;
      ratios[key] = {{"value", e["value"]}, {"unit", "x"}, {"description", e.value("description", json())},
                     {"poise", e.value("poise", json())}, {"baseline", e.value("baseline", json())}};
    }
    rb["ratios"] = ratios;
    ref["baselines"] = rb;
  } else if (o.is_object() && o.contains("baselines")) {
    ref["baselines"] = o["baselines"];
    ref["baselines"]["kept"] = "from the previous reference: the baselines did not run in the source run";
  }
  json s = json::object();
  const json run_studies = run.value("studies", json::object());
  for (const auto& [name, e] : run_studies.items()) {
    if (!e.contains("statistics")) continue;
    s[name] = {{"samples", e.value("samples", json())},
               {"seed", e.value("seed", json())},
               {"failures", e.value("failures", json())},
               {"study_file_sha1", e.value("study_file_sha1", json())},
               {"model_file_sha1", e.value("model_file_sha1", json())},
               {"statistics", e["statistics"]}};
  }
  ref["studies"] = s;
  write_json(out, ref);
  return kExitOk;
}

// ---------------------------------------------------------------------------------------------
// compare

struct Options {
  double k = 3.0;
  double floor = 0.05;
  double stat_rtol = 1e-9;
  double wall_warn = 0.25;
  // A baseline ratio regresses below previous (reference) / (1 + ratio_band): 0.2 catches a 1.3x
  // slowdown of Poise (ratio / 1.3 < ratio / 1.2) and leaves 20 % to the ratio's own scatter.
  double ratio_band = 0.2;
  bool all = false;
  bool warn_timing = false;  // timing regressions only warn (bench/nightly --quick: 2 repetitions)
  double gross = 0.5;        // ... unless worse by more than max(2 x band, gross)
  double idle_margin = 0.5;  // multi-threaded figures judged below load (cores - 1) + idle_margin
};

struct Tally {
  int compared = 0, warnings = 0, not_judged = 0;
  std::vector<std::string> regressions;
};

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::string full(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

std::string pct(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f%%", 100.0 * v);
  return buf;
}

std::string ratio_str(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", v);
  return buf;
}

std::optional<double> num(const json& j, const char* key) {
  if (j.is_object() && j.contains(key) && j[key].is_number()) return j[key].get<double>();
  return std::nullopt;
}

// worse = how much worse the current figure is than the other (> 0 worse), in relative terms
// of the figure's own sense: lower-better: cur/other - 1; higher-better: other/cur - 1.
double worse_by(double cur, double other, bool lower_better) {
  return lower_better ? cur / other - 1.0 : other / cur - 1.0;
}

struct Verdict {
  std::string text;
  bool regression = false;
};

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

// Baseline ratios (bench/baselines/compare.py): NumPy/SciPy CPU time over Poise's, measured in
// the same run, so a loaded machine slows both sides. Below the target: a warning; below the
// previous run's or the reference's ratio / (1 + ratio_band): a regression (a warning with
// --warn-timing). Baselines not run, a ratio not computed, or no reference ratio: never a failure.
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
    else if (a == "--stat-rtol")
      opt.stat_rtol = parse_double(value(), a);
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
  // A timing figure beyond its band: a regression, or with --warn-timing (a quick run's 2
  // repetitions cannot measure the noise) a warning, unless it is worse by more than twice its
  // band and by at least 50 %: a slowdown that large shows even in 2 repetitions.
  const auto gross = [&](double worse, double band) { return worse > std::max(2.0 * band, opt.gross); };
  const auto flag_timing = [&](const std::string& what, double worse, double band) {
    if (opt.warn_timing && !gross(worse, band))
      ++t.warnings;
    else
      t.regressions.push_back(what);
  };
  const auto warn_suffix = [&](const Verdict& v, double worse, double band) {
    return v.regression && opt.warn_timing && !gross(worse, band) ? std::string(" (warning)") : std::string();
  };
  // Multi-threaded figures (real time, 2-thread speed-ups) need the cores free: judged only when
  // the load average beside them is below (cores - 1) + idle_margin; otherwise a note.
  const int cores = cur.contains("machine") ? cur["machine"].value("nproc", 0) : 0;
  const auto too_loaded = [&](const json& e) -> std::string {
    if (!e.contains("load_avg") || !e["load_avg"].is_number() || cores <= 0) return "";
    const double load = e["load_avg"].get<double>();
    if (load < cores - 1 + opt.idle_margin) return "";
    char buf[96];
    std::snprintf(buf, sizeof buf, "not judged: load %.2f on %d cores", load, cores);
    ++t.not_judged;
    return buf;
  };
  std::printf("poise nightly compare\n  current:   %s\n", describe(cur, cur_path).c_str());
  std::printf("  previous:  %s\n", prev.is_null() ? "(none)" : describe(prev, prev_path).c_str());
  std::printf("  reference: %s\n", ref.is_null() ? "(none)" : ref_path.c_str());
  std::printf(
      "rule: a figure regresses when worse than the previous run or the reference by more than\n"
      "  band = max(%s, %.3g x sqrt(noise_current^2 + noise_other^2)). Benchmark figure: median time per\n"
      "  iteration (CPU; real for /real_time) / calibration median; noise: relative standard error of the\n"
      "  median(s), 1.2533 sd / sqrt(n) / median x t(0.975, n-1) / 1.96. Study statistics must equal the\n"
      "  reference to relative %.0e. Targets and study wall times only warn.%s\n",
      pct(opt.floor).c_str(), opt.k, opt.stat_rtol,
      opt.warn_timing ? "\n  --warn-timing (quick run): timing regressions only warn too." : "");

  const auto band_of = [&](double n1, double n2) { return std::max(opt.floor, opt.k * std::hypot(n1, n2)); };
  if (!prev.is_null() && cur.contains("machine") && prev.contains("machine") &&
      (cur["machine"].value("cpu_model", std::string()) != prev["machine"].value("cpu_model", std::string()) ||
       cur["machine"].value("nproc", 0) != prev["machine"].value("nproc", 0))) {
    std::printf(
        "note: the machine differs from the previous run's; absolute times are not comparable, the "
        "calibrated figures are.\n");
  }

  // Calibration itself (informative: the machine's speed).
  const json cal = cur.value("calibration", json::object());
  std::printf("\ncalibration: median %s ns/step, cv %s, spread %s (n %d)", fmt(cal.value("median", 0.0)).c_str(),
              pct(cal.value("cv", 0.0)).c_str(), pct(cal.value("spread", 0.0)).c_str(), cal.value("n", 0));
  if (!prev.is_null() && num(prev.value("calibration", json::object()), "median"))
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

  // Benchmarks.
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
    const std::string loaded = e.value("figure", std::string()) == "real_time" ? too_loaded(e) : std::string();
    if (!loaded.empty()) {
      if (pb.contains(key)) prev_s = fmt(pb[key].value("median", 0.0) * scale) + unit;
      std::printf("%-52s %10s %10s %6s %7s %7s %7s %7s  %s\n", key.c_str(), prev_s.c_str(),
                  (fmt(med * scale) + unit).c_str(), pct(noise).c_str(), "-", "-", "-", "-", loaded.c_str());
      continue;
    }
    if (pb.contains(key) && num(pb[key], "per_calibration") && pc > 0) {
      const double ppc = pb[key]["per_calibration"].get<double>();
      prev_s = fmt(pb[key].value("median", 0.0) * scale) + unit;
      const double band = band_of(noise, pb[key].value("noise_per_calibration", 0.0));
      const Verdict v = judge(pc, ppc, true, band);
      const double w = worse_by(pc, ppc, true);
      rp = ratio_str(pc / ppc), bp = pct(band);
      ++t.compared;
      if (v.regression) flag_timing(key + " vs previous (x" + rp + ", band " + bp + ")", w, band);
      verdicts.push_back(v.text == "ok" ? "ok" : v.text + " vs prev" + warn_suffix(v, w, band));
    } else if (!pb.empty()) {
      verdicts.push_back("new");
    }
    if (rb.contains(key) && num(rb[key], "per_calibration") && pc > 0) {
      const double rpc = rb[key]["per_calibration"].get<double>();
      const double band = band_of(noise, rb[key].value("noise", 0.0));
      const Verdict v = judge(pc, rpc, true, band);
      const double w = worse_by(pc, rpc, true);
      rr = ratio_str(pc / rpc), br = pct(band);
      ++t.compared;
      if (v.regression) flag_timing(key + " vs reference (x" + rr + ", band " + br + ")", w, band);
      verdicts.push_back(v.text == "ok" ? "ok" : v.text + " vs ref" + warn_suffix(v, w, band));
    }
    std::string verdict;
    for (const auto& v : verdicts) {
      if (v != "ok") verdict += (verdict.empty() ? "" : ", ") + v;
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

  // Derived figures: speed-ups compared (ratios already), absolute figures against targets.
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
    const std::string loaded = is_ratio ? too_loaded(e) : std::string();
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
        const double band = band_of(cv, pd[key].value("noise", 0.0));
        const Verdict vd = judge(v, pv, lower, band);
        const double w = worse_by(v, pv, lower);
        rp = ratio_str(v / pv), bp = pct(band);
        ++t.compared;
        if (vd.regression) flag_timing(key + " vs previous (" + fmt(pv) + " -> " + fmt(v) + ")", w, band);
        if (vd.text != "ok") verdicts.push_back(vd.text + " vs prev" + warn_suffix(vd, w, band));
      } else if (pv > 0) {
        rp = ratio_str(v / pv);
      }
    }
    if (is_ratio && rd.contains(key) && num(rd[key], "value") && v > 0) {
      const double rv = rd[key]["value"].get<double>();
      const double band = band_of(cv, rd[key].value("noise", 0.0));
      const Verdict vd = judge(v, rv, lower, band);
      const double w = worse_by(v, rv, lower);
      rr = ratio_str(v / rv), br = pct(band);
      ++t.compared;
      if (vd.regression) flag_timing(key + " vs reference (" + fmt(rv) + " -> " + fmt(v) + ")", w, band);
      if (vd.text != "ok") verdicts.push_back(vd.text + " vs ref" + warn_suffix(vd, w, band));
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

  compare_baselines(cur, prev, ref, opt, t);

  // Reference studies.
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
    if (ps.contains(name) && num(ps[name], "wall_s") &&
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

void print_help() {
  std::printf(
      "poise_nightly_compare: compare a nightly run (bench/nightly) with the previous run and the reference\n"
      "\n"
      "  poise_nightly_compare CURRENT.json [--previous PREV.json] [--reference REF.json] [options]\n"
      "      --k K           noise multiplier of the band (default 3)\n"
      "      --floor F       smallest band, relative (default 0.05 = 5%%)\n"
      "      --stat-rtol R   relative tolerance of reference-study statistics (default 1e-9)\n"
      "      --wall-warn W   warn when a study's wall time grows by more than W (default 0.25)\n"
      "      --all           print every statistic, not only the changed ones\n"
      "      --warn-timing   timing regressions only warn (bench/nightly --quick), unless worse by more than\n"
      "                      max(2 x band, G)\n"
      "      --gross G       (default 0.5: 1.5x slower)\n"
      "      --idle-margin M multi-threaded figures (real time, speed-ups) are judged only when the load\n"
      "                      average beside them is below (cores - 1) + M (default 0.5)\n"
      "      --ratio-band B  a baseline ratio regresses below previous/reference / (1+B) (default 0.2)\n"
      "  Rule: a benchmark figure is its median time per iteration (CPU time; real time for /real_time\n"
      "  runs) / the calibration median of the same run; it regresses when worse than previous/reference\n"
      "  by more than max(floor, k*sqrt(n1^2+n2^2)), n = the figures' noise (relative standard error of\n"
      "  the medians x t(0.975, n-1)/1.96, benchmark and calibration combined). Speed-ups (2 threads over 1)\n"
      "  likewise, judged only below a load of (cores - 1) + M. Study statistics and their 95 %% interval\n"
      "  ends (fixed seeds) must equal the reference to R. Targets: warnings only.\n"
      "  Baseline ratios (NumPy/SciPy CPU time / Poise's, one run): below previous/reference / (1+B) a\n"
      "  regression (1.3x slower Poise is caught at B 0.2); below target, not run or no reference: warnings.\n"
      "  Exit status: 0 fine (warnings allowed), 3 regression (listed at the end), 2 bad input or usage.\n"
      "\n"
      "  poise_nightly_compare calibrate [--repetitions N] [--min-time S]     time the calibration workload\n"
      "  poise_nightly_compare collect --out FILE --meta META.json [--calibration CAL.json]...\n"
      "        [--bench BINARY EXIT_STATUS BENCH.json]... [--study NAME EXIT_STATUS WALL_S SUMMARY.json]...\n"
      "        [--baselines BASELINES.json]    (bench/baselines/compare.py --json, or {\"status\": \"not run\"})\n"
      "        [--load NAME BEFORE AFTER]...   (1-minute load average around a binary; NAME study:S for a study)\n"
      "  poise_nightly_compare make-reference CURRENT.json --out REF.json [--old OLD_REF.json]\n"
      "\n"
      "See bench/NIGHTLY.md.\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (args.empty()) {
      print_help();
      return kExitInput;
    }
    if (args[0] == "--help" || args[0] == "-h") {
      print_help();
      return kExitOk;
    }
    const std::string mode = args[0];
    const std::vector<std::string> rest(args.begin() + 1, args.end());
    if (mode == "calibrate") return run_calibrate(rest);
    if (mode == "collect") return run_collect(rest);
    if (mode == "make-reference") return run_make_reference(rest);
    return run_compare(args);
  } catch (const InputError& e) {
    std::fprintf(stderr, "poise_nightly_compare: %s\n", e.what());
    return kExitInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "poise_nightly_compare: %s\n", e.what());
    return kExitInput;
  }
}
