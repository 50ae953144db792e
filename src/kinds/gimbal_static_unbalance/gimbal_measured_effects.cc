#include "kinds/gimbal_static_unbalance/gimbal_measured_effects.h"

#include <string>

#include "core/error.h"
#include "core/format.h"
#include "model_files/gimbal_model.h"

namespace poise::kinds::gimbal_static_unbalance {
namespace {
namespace est = poise::estimators;

std::string value(double v, const char* unit) { return fmt::format("{:.9g} {}", v, unit); }

double param(const est::Effect& e, const std::string& name) {
  for (const auto& p : e.params) {
    if (p.name == name) return p.value;
  }
  throw Error("effect " + e.name + " has no parameter " + name);
}

// The study's outputs that are errors of the simulated test (its RMSEs, mean errors and
// residuals), the torque error first; and its sine fit's residual.
void compared_outputs(const std::vector<engine::OutputSpec>& outputs, engine::EffectsInModel& out) {
  const auto has = [](const std::string& n, const char* part) { return n.find(part) != std::string::npos; };
  for (const auto& o : outputs) {
    if (!has(o.name, "error") && !has(o.name, "rmse") && !has(o.name, "residual")) continue;
    out.error_outputs.push_back(o.name);
    if (out.headline_output.empty() && has(o.name, "torque_error")) out.headline_output = o.name;
    if (out.fit_residual_output.empty() && has(o.name, "fit_rmse")) out.fit_residual_output = o.name;
  }
}

}  // namespace

engine::EffectsInModel gimbal_effects_in_model(const engine::StudyConfig& cfg,
                                               const std::vector<engine::OutputSpec>& outputs,
                                               const est::TorqueTable& table, const est::DiagnosisResult& result) {
  engine::EffectsInModel out;
  const model_files::GimbalModel model = model_files::load_gimbal_model(cfg.model_path);
  const double to_nm = table.unit_factor;
  for (const est::Effect& e : result.effects) {
    if (e.name == "harmonic" && e.order == 2) {
      out.overrides["disturbances.harmonic2_torque"] = value(param(e, "amplitude") * to_nm, "N*m");
      out.overrides["disturbances.harmonic2_phase"] = value(param(e, "phase_deg"), "deg");
    } else if (e.name == "time_drift" && !table.time_s.empty()) {
      out.overrides["disturbances.offset_drift_rate"] =
          value(param(e, "slope") * to_nm / model.plan.servo.kt_nominal, "A/s");
    } else if (e.name == "direction_offset") {
      out.overrides["disturbances.direction_torque"] = value(param(e, "half_difference") * to_nm, "N*m");
    } else if (e.name == "outlier") {
      out.overrides["disturbances.bump_position"] = std::to_string(e.index);
      out.overrides["disturbances.bump_torque"] = value(param(e, "offset") * to_nm, "N*m");
    } else {
      out.unmapped.push_back(e.name + (e.order ? " " + std::to_string(e.order) : "") +
                             (e.name == "time_drift" ? " (no time_s: no rate)" : ""));
    }
  }
  compared_outputs(outputs, out);
  return out;
}

}  // namespace poise::kinds::gimbal_static_unbalance
