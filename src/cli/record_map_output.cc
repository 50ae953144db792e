#include "cli/record_map_output.h"

#include <iterator>

#include "core/angles.h"
#include "core/format.h"

namespace poise::cli {
namespace {

nlohmann::json value_se(const estimators::OscillationParam& p, double factor = 1.0) {
  return {{"value", p.value * factor}, {"se", p.se * factor}};
}

nlohmann::json motion_json(const estimators::RecordMotion& m) {
  return {{"kind", m.kind},
          {"description", m.description},
          {"timed", m.timed},
          {"forward", m.forward},
          {"backward", m.backward},
          {"turns", m.turns},
          {"reversals", m.reversals},
          {"moving_share", m.moving_share},
          {"speed_turn_per_s", m.timed ? nlohmann::json(m.speed / angles::kTwoPi) : nlohmann::json(nullptr)},
          {"speed_variation", m.speed_variation}};
}

}  // namespace

nlohmann::json map_diagnosis_json(const estimators::MapDiagnosis& d) {
  nlohmann::json j;
  j["motion"] = motion_json(d.motion);
  j["n_samples"] = d.n;
  j["time"] = {{"median_step_s", d.motion.timed ? nlohmann::json(d.median_step) : nlohmann::json(nullptr)},
               {"gaps", d.gaps},
               {"gap_total_s", d.gap_total},
               {"gap_largest_s", d.gap_largest},
               {"gap_largest_line", d.gap_largest_line}};
  j["offset_mNm"] = value_se(d.offset, 1e3);
  if (d.coulomb_fitted) {
    j["coulomb_mNm"] = value_se(d.coulomb, 1e3);
    j["torque_forward_mNm"] = value_se(d.torque_forward, 1e3);
    j["torque_backward_mNm"] = value_se(d.torque_backward, 1e3);
  }
  j["cogging_map"] = nlohmann::json::array();
  for (const auto& o : d.orders) {
    j["cogging_map"].push_back({{"order", o.order},
                                {"amplitude_mNm", {{"value", o.amplitude * 1e3}, {"se", o.se_amplitude * 1e3}}},
                                {"phase_rad", {{"value", o.phase}, {"se", o.se_phase}}},
                                {"order_resolution", o.resolution},
                                {"p_value", o.p_value},
                                {"p_adjusted", o.p_adjusted},
                                {"delta_bic", o.delta_bic}});
  }
  j["effects"] = nlohmann::json::array();
  for (const auto& e : d.trends) {
    nlohmann::json ej{
        {"name", e.name}, {"p_value", e.p_value}, {"p_adjusted", e.p_adjusted}, {"delta_bic", e.delta_bic}};
    for (const auto& q : e.params) ej["params"][q.name] = {{"value", q.value}, {"se", q.se}, {"unit", q.unit}};
    j["effects"].push_back(ej);
  }
  j["not_identifiable"] = nlohmann::json::array();
  for (const auto& [name, why] : d.not_identifiable) j["not_identifiable"].push_back({{"name", name}, {"why", why}});
  j["outside_physics"] = d.outside_physics;
  j["rmse_constant_mNm"] = d.rmse_constant * 1e3;
  j["rmse_before_mNm"] = d.rmse_base * 1e3;
  j["rmse_after_mNm"] = d.rmse_after * 1e3;
  j["steps"] = nlohmann::json::array();
  for (const auto& s : d.steps) j["steps"].push_back({{"effect", s.effect}, {"rmse_mNm", s.rmse * 1e3}});
  return j;
}

std::string map_diagnosis_text(const estimators::MapDiagnosis& d, const estimators::OscillationRecord& record,
                               const std::string& torque_source) {
  std::string out;
  auto line = [&](const std::string& s) { out += s + "\n"; };
  line(fmt::format("Torque-against-angle diagnosis of {} ({} samples used, {})", record.file, d.n, torque_source));
  line("  motion: " + d.motion.description);
  for (const auto& note : record.notes) line("  read: " + note);
  if (d.motion.timed) {
    line(fmt::format(
        "  time: median step {} s; {}", significant(d.median_step, 4),
        d.gaps == 0 ? std::string("no gap")
                    : fmt::format("{} gap(s) over {} s, the largest {} s before line {}", d.gaps,
                                  significant(d.gap_total, 3), significant(d.gap_largest, 3), d.gap_largest_line)));
  }
  line("");
  line("  base model  torque = M_0" + std::string(d.coulomb_fitted ? " + C sign(phi')" : "") +
       " + sum_N T_N sin(N phi + psi_N)");
  line(fmt::format("    M_0 = {} +- {} mN*m", significant(d.offset.value * 1e3, 4), significant(d.offset.se * 1e3, 2)));
  if (d.coulomb_fitted) {
    line(fmt::format("    C   = {} +- {} mN*m (Coulomb friction: forward {} +- {}, backward {} +- {} mN*m)",
                     significant(d.coulomb.value * 1e3, 4), significant(d.coulomb.se * 1e3, 2),
                     significant(d.torque_forward.value * 1e3, 4), significant(d.torque_forward.se * 1e3, 2),
                     significant(d.torque_backward.value * 1e3, 4), significant(d.torque_backward.se * 1e3, 2)));
  }
  line("");
  line(
      fmt::format("  cogging map: {} order(s) found (amplitude T_N and phase psi_N with one standard error; "
                  "orders closer than +-{} are not told apart)",
                  d.orders.size(), d.orders.empty() ? std::string("-") : significant(d.orders.front().resolution, 2)));
  for (const auto& o : d.orders) {
    line(fmt::format("    order {:>4}  T = {} +- {} mN*m   psi = {} +- {} rad   p = {} (adjusted {})", o.order,
                     significant(o.amplitude * 1e3, 4), significant(o.se_amplitude * 1e3, 2), significant(o.phase, 4),
                     significant(o.se_phase, 2), significant(o.p_value, 2), significant(o.p_adjusted, 2)));
  }
  for (const auto& e : d.trends) {
    line(fmt::format("  * {}: slope {} +- {} N*m/s (p adjusted {}); causes: {}", e.name,
                     significant(e.params.at(0).value, 4), significant(e.params.at(0).se, 2),
                     significant(e.p_adjusted, 2), e.causes));
  }
  for (const auto& s : d.outside_physics) line("  outside physics (not a finding): " + s);
  for (const auto& [name, why] : d.not_identifiable) line("  not identifiable from this motion: " + name + ": " + why);
  line("");
  std::string steps = fmt::format("  torque residual RMS  {} (mean only) -> {} (base)",
                                  significant(d.rmse_constant * 1e3, 4), significant(d.rmse_base * 1e3, 4));
  for (const auto& s : d.steps) steps += fmt::format(" -> {} ({})", significant(s.rmse * 1e3, 4), s.effect);
  line(steps + " mN*m");
  if (!d.orders.empty()) {
    line("  into the model ([[rotor.cogging]] of a gimbal model, one table per order):");
    for (const auto& o : d.orders) {
      line(fmt::format("    [[rotor.cogging]] order = {}, torque = \"{} N*m\", phase = \"{} rad\"", o.order,
                       significant(o.amplitude, 4), significant(o.phase, 4)));
    }
  }
  return out;
}

}  // namespace poise::cli
