#include "cli/diagnose_loop.h"

#include <cmath>
#include <map>
#include <numeric>
#include <optional>

#include "core/error.h"
#include "core/format.h"
#include "engine/kind_interface/study_evaluation.h"
#include "engine/kind_interface/study_kind.h"
#include "engine/study_files/study_config.h"

namespace poise::cli {
namespace est = poise::estimators;
namespace {

void mean_sd(const std::vector<double>& v, double& mean, double& sd) {
  mean = v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  double ss = 0.0;
  for (double x : v) ss += (x - mean) * (x - mean);
  sd = v.size() > 1 ? std::sqrt(ss / static_cast<double>(v.size() - 1)) : 0.0;
}

// The kinds whose models take measured effects, for a message.
std::string kinds_taking_effects() {
  std::string names;
  for (const engine::StudyKind* k : engine::study_kinds()) {
    if (k->takes_measured_effects()) names += (names.empty() ? "" : ", ") + k->name();
  }
  return names.empty() ? "none" : names;
}

}  // namespace

LoopResult close_the_loop(const std::string& study_path, const est::TorqueTable& table,
                          const est::DiagnosisResult& result, std::size_t samples) {
  LoopResult out;
  out.study = study_path;
  out.samples = samples;
  out.measured_rmse = result.rmse_before;
  out.unit = table.unit;
  engine::StudyConfig cfg = engine::load_study(study_path);
  const std::optional<engine::EffectsInModel> mapped =
      engine::study_kind(cfg.kind).effects_in_model(cfg, table, result);
  if (!mapped) {
    throw Error(study_path + ": study kind '" + cfg.kind + "': its model takes no effect measured in a test table (" +
                "kinds whose models do: " + kinds_taking_effects() + ")");
  }
  for (const auto& [k, v] : mapped->overrides) out.overrides.emplace_back(k, v);
  out.unmapped = mapped->unmapped;
  if (mapped->overrides.empty()) {
    out.sentence = "No effect found maps to a key of the simulation model: the study is not re-run.";
    return out;
  }
  const engine::McResult without = engine::evaluate_study(cfg, {}, samples, cfg.seed, 0);
  const engine::McResult with = engine::evaluate_study(cfg, mapped->overrides, samples, cfg.seed, 0);
  for (const std::string& name : mapped->error_outputs) {
    LoopOutput o;
    o.name = name;
    mean_sd(without.values[without.index(name)], o.mean_without, o.sd_without);
    mean_sd(with.values[with.index(name)], o.mean_with, o.sd_with);
    out.outputs.push_back(o);
  }
  const LoopOutput* err = out.outputs.empty() ? nullptr : &out.outputs.front();
  const LoopOutput* fit = nullptr;
  for (const LoopOutput& o : out.outputs) {
    if (o.name == mapped->headline_output) err = &o;
    if (o.name == mapped->fit_residual_output) fit = &o;
  }
  if (err) {
    out.sentence = fmt::format(
        "With these effects in the model the simulated test's {} is {:.4g} +- {:.3g} "
        "(mean +- sd over {} samples; {:.4g} +- {:.3g} without them)",
        err->name, err->mean_with, err->sd_with, samples, err->mean_without, err->sd_without);
    if (fit) {
      out.sentence +=
          fmt::format("; its fit residual {} is {:.4g} ({:.4g} without)", fit->name, fit->mean_with, fit->mean_without);
    }
    out.sentence += fmt::format(
        "; the measured table leaves {:.4g} {} rms about Eq. 22 ({:.4g} after the "
        "diagnosis).",
        result.rmse_before, table.unit, result.rmse_after);
  } else {
    out.sentence = "The study has no error output to compare.";
  }
  return out;
}

nlohmann::json loop_json(const LoopResult& r) {
  nlohmann::json j = {{"study", r.study},
                      {"samples", r.samples},
                      {"overrides", nlohmann::json::object()},
                      {"unmapped", r.unmapped},
                      {"outputs", nlohmann::json::array()},
                      {"measured_rmse", r.measured_rmse},
                      {"unit", r.unit},
                      {"sentence", r.sentence}};
  for (const auto& [k, v] : r.overrides) j["overrides"][k] = v;
  for (const LoopOutput& o : r.outputs) {
    j["outputs"].push_back({{"name", o.name},
                            {"mean_without", o.mean_without},
                            {"sd_without", o.sd_without},
                            {"mean_with", o.mean_with},
                            {"sd_with", o.sd_with}});
  }
  return j;
}

std::string loop_text(const LoopResult& r) {
  std::string s = "\nClosing the loop with " + r.study + ":\n";
  for (const auto& [k, v] : r.overrides) s += "  " + k + " = " + v + "\n";
  for (const auto& u : r.unmapped) s += "  " + u + ": no key of the simulation model maps to it\n";
  for (const LoopOutput& o : r.outputs) {
    s += fmt::format("  {}: without {:.4g} +- {:.3g}, with {:.4g} +- {:.3g}\n", o.name, o.mean_without, o.sd_without,
                     o.mean_with, o.sd_with);
  }
  return s + "  " + r.sentence + "\n";
}

}  // namespace poise::cli
