// make-reference: the reference figures (bench/nightly_reference.json) from a run, the targets
// kept from the old reference when given.
#include <string>
#include <vector>

#include "nightly_common.h"
#include "nightly_modes.h"

namespace poise::nightly {

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
               "Written by bench/nightly --update-reference; the figures of the run below. Benchmark "
               "figures are times relative to the calibration workload with their noise. Targets are "
               "warn-only. The studies' references are tests/data/study_reference/ (record.sh)."},
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
  // No study figures: each study has one recorded reference, tests/data/study_reference/.
  write_json(out, ref);
  return kExitOk;
}

}  // namespace poise::nightly
