#include "cli/budget_monte_carlo.h"

#include <thread>

#include "core/error.h"
#include "kinds/seeker_los/seeker_los_sections.h"
#include "kinds/seeker_los/seeker_los_study.h"
#include "kinds/seeker_los/seeker_model.h"
#include "engine/toml_reader.h"

namespace poise::cli {
namespace {

std::vector<MonteCarloOutput> seeker_outputs() {
  std::vector<MonteCarloOutput> out;
  for (const auto& o : studies::kSeekerOutputs) out.push_back({o.name, o.unit, o.description});
  return out;
}

std::vector<std::string> seeker_tolerance_keys(const std::string& model_path) {
  const studies::SeekerModel m = studies::load_seeker_model(model_path);
  std::vector<std::string> keys = m.tolerance_keys();
  keys.insert(keys.begin(), "load_deformation");  // k', sampled too (SeekerSampler's k_load)
  return keys;
}

// Plain Monte Carlo (independent samples, so the quantile's order-statistic interval holds) of
// the seeker chain over a 13 x 13 grid of the field of regard, as the LOS study does.
MonteCarloValues seeker_run(const std::string& model_path, const std::string& output, std::size_t samples,
                            std::uint64_t seed) {
  studies::StudyConfig cfg;
  cfg.kind = "seeker_los";
  cfg.name = "budget_monte_carlo";
  cfg.model_path = model_path;
  cfg.method = sampling::SamplingMethod::kMonteCarlo;
  cfg.samples = samples;
  cfg.seed = seed;
  cfg.plots = false;
  auto sections = std::make_unique<studies::SeekerLosSections>();  // a 13 x 13 grid
  sections->requirement = 1.0;  // 1 px: only the field_ok_fraction output depends on it
  sections->requirement_in_pixels = true;
  sections->contribution_samples = 0;
  cfg.sections = std::move(sections);
  std::size_t column = studies::kNumSeekerOutputs;
  for (std::size_t k = 0; k < studies::kNumSeekerOutputs; ++k) {
    if (output == studies::kSeekerOutputs[k].name) column = k;
  }
  require(column < studies::kNumSeekerOutputs, "seeker Monte Carlo: no output \"" + output + "\"");
  const studies::SeekerLosStudy study(cfg, studies::load_seeker_model(model_path), samples, seed);
  const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const studies::SeekerMcResult r = study.run(threads, false, {}, studies::outputs_only());
  MonteCarloValues v;
  v.samples = samples;
  v.failures = r.failures;
  v.wall_seconds = r.wall_seconds;
  if (column < r.values.size()) v.values = r.values[column];
  return v;
}

}  // namespace

const std::vector<MonteCarloKind>& monte_carlo_kinds() {
  static const std::vector<MonteCarloKind> kinds = {
      {"seeker_two_axis", "LOS error of the two-axis seeker chain over its field of regard (seeker_los study)",
       seeker_outputs, seeker_tolerance_keys, seeker_run},
  };
  return kinds;
}

const MonteCarloKind* find_monte_carlo_kind(const std::string& model_kind) {
  for (const auto& k : monte_carlo_kinds()) {
    if (k.model_kind == model_kind) return &k;
  }
  return nullptr;
}

std::string model_kind_of(const std::string& model_path) {
  const toml::table doc = studies::parse_toml_file(model_path);
  if (const auto* kind = doc["model"]["kind"].as_string()) return kind->get();
  return "";
}

}  // namespace poise::cli
