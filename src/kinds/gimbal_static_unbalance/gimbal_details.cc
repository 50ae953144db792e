// GimbalStudy's summary.json "details" and its report section: the share of samples a
// saturated drive or an out-of-range swing failed, the error mechanism, the counterweight
// placement, and the plausibility warnings of the model's calibrated tolerances.
#include "core/format.h"
#include "engine/results/result_io.h"
#include "kinds/gimbal_static_unbalance/gimbal_sections.h"
#include "kinds/gimbal_static_unbalance/gimbal_study.h"

namespace poise::kinds::gimbal_static_unbalance {
using namespace poise::model_files;
using namespace poise::engine;
namespace {

nlohmann::json share_json(std::size_t count, std::size_t ran) {
  const sampling::Estimate e = sampling::fraction_wilson(count, std::max<std::size_t>(ran, 1));
  return {{"count", count},
          {"samples", ran},
          {"share", ran > 0 ? e.value : 0.0},
          {"ci95",
           {e.lo ? nlohmann::json(*e.lo) : nlohmann::json(nullptr),
            e.hi ? nlohmann::json(*e.hi) : nlohmann::json(nullptr)}},
          {"unit", "share of the samples (1 = all)"}};
}

std::size_t count_of(const McResult& mc, const char* reason) {
  const auto it = mc.failure_reasons.find(reason);
  return it == mc.failure_reasons.end() ? 0 : it->second;
}

}  // namespace

nlohmann::json GimbalStudy::details(const McResult& mc) const {
  nlohmann::json placements = nlohmann::json::object();
  for (const auto& g : gimbal_sections(config_).groups) {
    placements[g.name] =
        g.counterweight_placement == "model" ? model_.counterweight_placement : g.counterweight_placement;
  }
  return {{"saturated_share", share_json(count_of(mc, "drive saturated"), mc.completed)},
          {"swing_out_of_range_share", share_json(count_of(mc, "swing out of range"), mc.completed)},
          {"swing_range_deg", model_.plan.oscillation.swing_range / units::kRadPerDeg},
          {"drive_limit_mNm", model_.plan.servo.current_limit * model_.plan.servo.kt_nominal * 1e3},
          {"error_mechanism", model_.error_mechanism},
          {"counterweight_placement", placements},
          {"plausibility_warnings", plausibility_warnings(model_)}};
}

void GimbalStudy::report_sections(const McResult& mc, const std::string&, bool, std::vector<std::string>&,
                                  std::ostringstream& h) const {
  const nlohmann::json d = details(mc);
  h << "<h2>Drive saturation and swing range</h2>\n";
  h << fmt::format(
      "<p>A position whose drive current reaches its limit ({:.4g} mN*m at the nominal K_T) or whose swing "
      "leaves the test's stated range (+-{:.4g} deg) fails its sample with the reason. Saturated: {} of {} "
      "samples (share {:.3g}); swing out of range: {}.</p>\n",
      d["drive_limit_mNm"].get<double>(), d["swing_range_deg"].get<double>(),
      d["saturated_share"]["count"].get<std::size_t>(), mc.completed, d["saturated_share"]["share"].get<double>(),
      d["swing_out_of_range_share"]["count"].get<std::size_t>());
  h << "<h2>Per-test error mechanism and counterweight placement</h2>\n<p>Mechanism: <code>"
    << html_escape(model_.error_mechanism) << "</code>. Counterweight placement per group:";
  for (const auto& [g, p] : d["counterweight_placement"].items()) {
    h << " " << html_escape(g) << " <code>" << html_escape(p.get<std::string>()) << "</code>;";
  }
  h << " residuals are taken about the bearing axis, the run-out's m r included.</p>\n";
  if (!d["plausibility_warnings"].empty()) {
    h << "<p><b>Warning: calibrated tolerances past their physically plausible range</b> ([plausibility] of the "
         "model):</p>\n<ul>\n";
    for (const auto& w : d["plausibility_warnings"]) h << "<li>" << html_escape(w.get<std::string>()) << "</li>\n";
    h << "</ul>\n";
  }
}

}  // namespace poise::kinds::gimbal_static_unbalance
