#include "engine/run/procedure_contributions.h"
#include "core/diagnostics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "engine/report/report_figures.h"
#include "engine/report/report_plot.h"
#include "engine/results/requirements.h"
#include "engine/results/result_io.h"
#include "engine/run/runs_over_ranks.h"
#include "engine/study_files/toml_reader.h"
#include "sampling/distributed.h"

namespace poise::engine {
namespace {
using nlohmann::json;

// "0 <unit>" for a tolerance written "<number> <unit>" at `key` + ".tolerance" (an override
// of the study first, else the model file); nullopt when it is a range or not there.
std::optional<std::string> zero_of(const StudyConfig& cfg, const toml::table& model, const std::string& key) {
  std::string text;
  if (const auto it = cfg.overrides.find(key + ".tolerance"); it != cfg.overrides.end()) {
    text = it->second;
  } else if (const auto* node = model.at_path(key + ".tolerance").as_string()) {
    text = node->get();
  } else if (const auto* number = model.at_path(key + ".tolerance").node(); number && (number->is_number())) {
    return std::string("0");
  } else {
    return std::nullopt;
  }
  const auto space = text.find_first_of(" \t%");
  std::string zero = "0";
  if (space != std::string::npos) zero.append(text, space, std::string::npos);
  return zero;
}

json run_without(const StudyConfig& cfg, const StudyFactory& make_study,
                 const std::map<std::string, std::string>& extra, std::size_t samples, std::uint64_t seed, int threads,
                 const std::vector<OutputSpec>& outputs) {
  StudyConfig c = cfg;
  auto overrides = c.overrides;
  for (const auto& [k, v] : extra) overrides[k] = v;
  c.overrides = apply_study_overrides(c, overrides);
  const McResult mc = make_study(c, samples, seed)->run(threads, false, {}, {});
  return {{"samples", mc.completed}, {"failures", mc.failures}, {"outputs", outputs_json(mc, outputs, false)}};
}

}  // namespace

json run_procedure_contributions(const StudyConfig& cfg, const StudyFactory& make_study,
                                 const std::vector<std::string>& tolerance_keys, std::size_t samples,
                                 std::uint64_t seed, int threads, bool progress,
                                 const std::vector<OutputSpec>& outputs) {
  json out = json::array();
  const toml::table model = parse_toml_file(cfg.model_path);
  std::vector<std::string> keys;
  for (const auto& k : tolerance_keys) {
    if (!k.empty() && std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
  }
  if (progress) {
    const int ranks = sampling::Cluster::size();
    diagnostics::progress("  contributions: " + std::to_string(keys.size() + 1) + " runs of " +
                          std::to_string(samples) + " samples" +
                          (ranks > 1 ? " over " + std::to_string(ranks) + " MPI ranks" : std::string()));
  }
  // Run 0 with every tolerance, run k without keys[k - 1]: each a run of its own, spread over
  // the MPI ranks, if any.
  const std::vector<json> results = runs_over_ranks(keys.size() + 1, [&](std::size_t i) -> json {
    if (i == 0) {
      json all = run_without(cfg, make_study, {}, samples, seed, threads, outputs);
      all["without"] = "(nothing: all tolerances)";
      return all;
    }
    const std::string& key = keys[i - 1];
    const std::optional<std::string> zero = zero_of(cfg, model, key);
    if (!zero) {
      return {{"without", key}, {"skipped", "given as a range (min, max) or with no tolerance value: no zero"}};
    }
    try {
      json j = run_without(cfg, make_study, {{key + ".tolerance", *zero}}, samples, seed, threads, outputs);
      j["without"] = key;
      return j;
    } catch (const ValidationError& e) {
      return {{"without", key}, {"skipped", std::string("the model refuses it at zero: ") + e.what()}};
    }
  });
  if (!sampling::Cluster::root()) return nullptr;
  for (const json& r : results) out.push_back(r);
  return out;
}

}  // namespace poise::engine
