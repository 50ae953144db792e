#include "cli/diagnose_loop.h"

#include <cmath>
#include <map>
#include <numeric>

#include "core/error.h"
#include "core/format.h"
#include "engine/kind_interface/study_evaluation.h"
#include "engine/study_files/study_config.h"
#include "model_files/gimbal_model.h"

using namespace poise::model_files;  // the kinds' and model files' own namespaces

namespace poise::cli {
namespace {

namespace est = poise::estimators;

std::string value(double v, const char* unit) { return fmt::format("{:.9g} {}", v, unit); }

double param(const est::Effect& e, const std::string& name) {
  for (const auto& p : e.params) {
    if (p.name == name) return p.value;
  }
  throw Error("effect " + e.name + " has no parameter " + name);
}

void mean_sd(const std::vector<double>& v, double& mean, double& sd) {
  mean = v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  double ss = 0.0;
  for (double x : v) ss += (x - mean) * (x - mean);
  sd = v.size() > 1 ? std::sqrt(ss / static_cast<double>(v.size() - 1)) : 0.0;
}

bool is_error_output(const std::string& n) {
  return n.find("error") != std::string::npos || n.find("rmse") != std::string::npos ||
         n.find("residual") != std::string::npos;
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
  if (cfg.kind != "gimbal_static_unbalance") {
    throw Error(study_path + ": study kind '" + cfg.kind +
                "'; expected gimbal_static_unbalance (its model has the [disturbances] an effect "
                "maps to)");
  }
  const model_files::GimbalModel model = model_files::load_gimbal_model(cfg.model_path);
  const double to_nm = table.unit_factor;
  std::map<std::string, std::string> overrides;
  for (const est::Effect& e : result.effects) {
    if (e.name == "harmonic" && e.order == 2) {
      overrides["disturbances.harmonic2_torque"] = value(param(e, "amplitude") * to_nm, "N*m");
      overrides["disturbances.harmonic2_phase"] = value(param(e, "phase_deg"), "deg");
    } else if (e.name == "time_drift" && !table.time_s.empty()) {
      overrides["disturbances.offset_drift_rate"] =
          value(param(e, "slope") * to_nm / model.plan.servo.kt_nominal, "A/s");
    } else if (e.name == "direction_offset") {
      overrides["disturbances.direction_torque"] = value(param(e, "half_difference") * to_nm, "N*m");
    } else if (e.name == "outlier") {
      overrides["disturbances.bump_position"] = std::to_string(e.index);
      overrides["disturbances.bump_torque"] = value(param(e, "offset") * to_nm, "N*m");
    } else {
      out.unmapped.push_back(e.name + (e.order ? " " + std::to_string(e.order) : "") +
                             (e.name == "time_drift" ? " (no time_s: no rate)" : ""));
    }
  }
  for (const auto& [k, v] : overrides) out.overrides.emplace_back(k, v);
  if (overrides.empty()) {
    out.sentence = "No effect found maps to a key of the simulation model: the study is not re-run.";
    return out;
  }
  const engine::McResult without = engine::evaluate_study(cfg, {}, samples, cfg.seed, 0);
  const engine::McResult with = engine::evaluate_study(cfg, overrides, samples, cfg.seed, 0);
  for (std::size_t i = 0; i < without.names.size(); ++i) {
    if (!is_error_output(without.names[i])) continue;
    LoopOutput o;
    o.name = without.names[i];
    mean_sd(without.values[i], o.mean_without, o.sd_without);
    mean_sd(with.values[with.index(o.name)], o.mean_with, o.sd_with);
    out.outputs.push_back(o);
  }
  const auto find = [&](const char* part) -> const LoopOutput* {
    for (const LoopOutput& o : out.outputs) {
      if (o.name.find(part) != std::string::npos) return &o;
    }
    return nullptr;
  };
  const LoopOutput* err = find("torque_error");
  if (!err && !out.outputs.empty()) err = &out.outputs.front();
  const LoopOutput* fit = find("fit_rmse");
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
