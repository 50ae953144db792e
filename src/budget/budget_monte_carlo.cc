#include "budget/budget_monte_carlo.h"

#include <thread>

#include "core/error.h"
#include "engine/kind_interface/study_kind.h"
#include "engine/study_files/toml_reader.h"
#include "sampling/distributed.h"

namespace poise::budget {
namespace {

// A kind's Monte Carlo on a model file alone, through the kind interface (StudyKind::
// model_study and evaluate): the output's values of every sample that did not fail.
MonteCarloValues run_kind(const engine::StudyKind& kind, const std::string& model_path, const std::string& output,
                          std::size_t samples, std::uint64_t seed) {
  const int threads = sampling::Cluster::default_threads();
  const engine::McResult e = kind.evaluate(kind.model_study(model_path), {}, samples, seed, threads);
  MonteCarloValues v;
  v.samples = e.n;
  v.failures = e.failures;
  v.wall_seconds = e.wall_seconds;
  v.values = e.values.at(e.index(output));
  return v;
}

}  // namespace

std::vector<MonteCarloKind> monte_carlo_kinds() {
  std::vector<MonteCarloKind> out;
  for (const engine::StudyKind* kind : engine::study_kinds()) {
    if (kind->model_kind().empty()) continue;
    out.push_back({kind->model_kind(), kind->summary(),
                   [kind](const std::string& model_path) {
                     std::vector<MonteCarloOutput> outputs;
                     for (const auto& o : kind->outputs(kind->model_study(model_path)))
                       outputs.push_back({o.name, o.unit, o.description});
                     return outputs;
                   },
                   [kind](const std::string& model_path) { return kind->model_tolerance_keys(model_path); },
                   [kind](const std::string& model_path, const std::string& output, std::size_t samples,
                          std::uint64_t seed) { return run_kind(*kind, model_path, output, samples, seed); }});
  }
  return out;
}

std::optional<MonteCarloKind> find_monte_carlo_kind(const std::string& model_kind) {
  for (auto& k : monte_carlo_kinds()) {
    if (k.model_kind == model_kind) return k;
  }
  return std::nullopt;
}

std::string model_kind_of(const std::string& model_path) {
  const toml::table doc = engine::parse_toml_file(model_path);
  if (const auto* kind = doc["model"]["kind"].as_string()) return kind->get();
  return "";
}

}  // namespace poise::budget
