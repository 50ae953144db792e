#include "cli/record_swing_output.h"

#include <fmt/printf.h>

#include "core/format.h"

namespace poise::cli {

nlohmann::json swing_diagnosis_json(const estimators::OscillationDiagnosis& d, const estimators::RecordMotion& motion,
                                    const estimators::OscillationRecord& record) {
  nlohmann::json j;
  auto p = [](const estimators::OscillationParam& q, double f) {
    return nlohmann::json{{"value", q.value * f}, {"se", q.se * f}};
  };
  j["n_samples"] = d.n;
  j["motion"] = {{"kind", motion.kind},
                 {"description", motion.description},
                 {"turns", motion.turns},
                 {"reversals", motion.reversals}};
  j["reading"] = record.notes;
  j["time"] = {{"median_step_s", d.median_step},
               {"gaps", d.gaps},
               {"gap_total_s", d.gap_total},
               {"gap_largest_s", d.gap_largest},
               {"gap_largest_line", d.gap_largest_line}};
  j["torque_eq21_mNm"] = d.torque_eq21 * 1e3;
  j["torque_before_mNm"] = p(d.torque_before, 1e3);
  j["torque_after_mNm"] = p(d.torque_after, 1e3);
  j["rmse_before_mNm"] = d.rmse_before * 1e3;
  j["rmse_after_mNm"] = d.rmse_after * 1e3;
  j["base_model"] = nlohmann::json::object();
  for (const auto& b : d.base_before) j["base_model"][b.name] = {{"value", b.value}, {"se", b.se}, {"unit", b.unit}};
  j["effects"] = nlohmann::json::array();
  for (const auto& e : d.effects) {
    nlohmann::json ej{{"name", e.name},
                      {"p_value", e.p_value},
                      {"p_adjusted", e.p_adjusted},
                      {"delta_bic", e.delta_bic},
                      {"causes", e.causes}};
    if (e.name == "cogging") ej["order"] = e.order, ej["order_resolution"] = e.order_resolution;
    for (const auto& q : e.params) ej["params"][q.name] = {{"value", q.value}, {"se", q.se}, {"unit", q.unit}};
    j["effects"].push_back(ej);
  }
  j["not_identifiable"] = nlohmann::json::array();
  for (const auto& [name, why] : d.not_identifiable) j["not_identifiable"].push_back({{"name", name}, {"why", why}});
  return j;
}

std::string swing_diagnosis_text(const estimators::OscillationDiagnosis& d, const estimators::RecordMotion& motion,
                                 const estimators::OscillationRecord& record, const std::string& torque_source) {
  std::string out;
  out += fmt::sprintf("Time-series diagnosis of %s (%zu samples used, %s)\n", record.file.c_str(), d.n,
                      torque_source.c_str());
  out += fmt::sprintf("  motion: %s\n", motion.description.c_str());
  for (const auto& note : record.notes) out += fmt::sprintf("  read: %s\n", note.c_str());
  out += fmt::sprintf(
      "  time: median step %s s; %s\n\n", significant(d.median_step, 4).c_str(),
      d.gaps == 0 ? "no gap"
                  : fmt::format("{} gap(s) over {} s, the largest {} s before line {} (each stretch derived "
                                "on its own)",
                                d.gaps, significant(d.gap_total, 3), significant(d.gap_largest, 3), d.gap_largest_line)
                        .c_str());
  out += fmt::sprintf("  base model  K_T i = J phi'' + B phi' + C sign(phi') [+ K phi] + M_0\n");
  for (const auto& b : d.base_before)
    out += fmt::sprintf("    %-2s = %.4g +- %.2g %s\n", b.name.c_str(), b.value, b.se, b.unit.c_str());
  out += fmt::sprintf("\n  effects found: %zu\n", d.effects.size());
  for (const auto& e : d.effects) {
    const std::string order =
        e.name == "cogging"
            ? fmt::format(
                  " of order {} +- {:.0f} per turn (orders closer than one cycle over the swing are not told apart)",
                  e.order, e.order_resolution)
            : "";
    out += fmt::sprintf("  * %s%s  p = %.2g (Holm %.2g), delta BIC = %.1f\n", e.name.c_str(), order.c_str(), e.p_value,
                        e.p_adjusted, e.delta_bic);
    for (const auto& q : e.params)
      out += fmt::sprintf("      %s = %.4g +- %.2g %s\n", q.name.c_str(), q.value, q.se, q.unit.c_str());
    out += fmt::sprintf("      causes: %s\n", e.causes.c_str());
    if (e.name == "cogging") {  // close the loop: the effect, as the simulation model takes it
      out += fmt::sprintf(
          "      into the model: --set rotor.cogging_torque=\"%.4g N*m\" --set rotor.cogging_order=%d "
          "--set rotor.cogging_phase=\"%.4g rad\"\n"
          "        (or, in the model file: [[rotor.cogging]] order = %d, torque = \"%.4g N*m\", phase = \"%.4g "
          "rad\")\n",
          e.params[0].value, e.order, e.params[1].value, e.order, e.params[0].value, e.params[1].value);
    }
  }
  for (const auto& [name, why] : d.not_identifiable)
    out += fmt::sprintf("  not identifiable here: %s: %s\n", name.c_str(), why.c_str());
  out += fmt::sprintf("\n  torque residual RMS  %.4f -> %.4f mN*m\n", d.rmse_before * 1e3, d.rmse_after * 1e3);
  out +=
      fmt::sprintf("  position torque: Eq. 21 %.4f mN*m; M_0 base %.4f +- %.4f; with the effects %.4f +- %.4f mN*m\n",
                   d.torque_eq21 * 1e3, d.torque_before.value * 1e3, d.torque_before.se * 1e3,
                   d.torque_after.value * 1e3, d.torque_after.se * 1e3);
  return out;
}

}  // namespace poise::cli
