// The analysis as `poise balance --json` prints it (balancing/campaign_analysis.h: analysis_json),
// one function per part of the object.
#include <cmath>

#include <nlohmann/json.hpp>

#include "balancing/campaign_analysis.h"
#include "balancing/iso_figures.h"

namespace poise::balancing {
namespace {
using estimators::Phasor;
using estimators::PhasorInterval;
using nlohmann::json;

json maybe(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

json phasor_json(const Phasor& z) { return {{"amplitude", std::abs(z)}, {"angle_deg", degrees(z)}}; }

// A complex answer: its size (under `amount_key`, times `factor`), angle, the 95% region's largest
// half axis (under `radius_key`) and its degrees of freedom.
json interval_json(const PhasorInterval& z, const std::string& amount_key, const std::string& radius_key,
                   double factor) {
  const auto r = z.radius();
  return {{amount_key, std::abs(z.value) * factor},
          {"angle_deg", degrees(z.value)},
          {radius_key, r ? json(*r * factor) : json(nullptr)},
          {"degrees_of_freedom", r ? json(z.dof) : json(nullptr)}};
}

json plane_answers_json(const BalancingCampaign& c, const CampaignAnalysis& a, const estimators::PlaneAnswers& u,
                        const std::optional<std::vector<Phasor>>& applied) {
  json planes = json::array();
  for (std::size_t p = 0; p < c.planes.size(); ++p) {
    json e = interval_json(u.planes[p], "mass_g", "radius95_g", 1.0);
    e["plane"] = c.planes[p];
    if (applied) {
      e["applied"] = {{"mass_g", std::abs((*applied)[p])}, {"angle_deg", degrees((*applied)[p])}};
      e["covered"] = u.planes[p].radius() ? json(u.planes[p].contains((*applied)[p])) : json(nullptr);
      e["error_g"] = std::abs(u.planes[p].value - (*applied)[p]);
    }
    planes.push_back(e);
  }
  json j{{"planes", planes}};
  if (u.static_unbalance) {
    j["static"] = interval_json(*u.static_unbalance, "amount", "radius95", a.moment_factor);
    j["couple"] = interval_json(*u.couple_unbalance, "amount", "radius95", a.moment_factor);
    j["unit"] = a.moment_unit;
  }
  return j;
}

json coefficients_json(const BalancingCampaign& c, const estimators::InfluenceCalibration& cal) {
  json h = json::array();
  for (std::size_t s = 0; s < c.sensors.size(); ++s) {
    for (std::size_t p = 0; p < c.planes.size(); ++p) {
      h.push_back({{"sensor", c.sensors[s]},
                   {"plane", c.planes[p]},
                   {"value", phasor_json(cal.h[s][p].value)},
                   {"standard_error", maybe(cal.h[s][p].se)}});
    }
  }
  return h;
}

// The correction per plane, with its split onto the plane's holes where it has them.
json correction_json(const BalancingCampaign& c, const CampaignAnalysis& a) {
  json masses = json::array();
  for (std::size_t p = 0; p < c.planes.size(); ++p) {
    json e = interval_json(a.correction_masses.planes[p], "mass_g", "radius95_g", 1.0);
    e["plane"] = c.planes[p];
    if (!a.correction_holes[p].empty()) {
      e["holes"] = json::array();
      for (const auto& hole : a.correction_holes[p]) {
        e["holes"].push_back({{"angle_deg", degrees(std::polar(1.0, hole.angle))}, {"mass_g", hole.mass_g}});
      }
    }
    masses.push_back(e);
  }
  return masses;
}

json residual_json(const BalancingCampaign& c, const CampaignAnalysis& a) {
  json residual = json::array();
  for (std::size_t s = 0; s < c.sensors.size(); ++s) {
    const auto& z = a.residual_as_read[s];
    residual.push_back({{"sensor", c.sensors[s]}, {"reading", phasor_json(z.value)}, {"radius95", maybe(z.radius())}});
  }
  return residual;
}

json readings_json(const BalancingCampaign& c, const CampaignAnalysis& a) {
  json out = json::array();
  for (const auto& pt : a.points) {
    out.push_back({{"run", pt.run},
                   {"sensor", c.sensors[pt.sensor]},
                   {"check", pt.check},
                   {"reading", phasor_json(pt.reading)},
                   {"model", pt.model ? phasor_json(*pt.model) : json(nullptr)}});
  }
  return out;
}

// ISO 21940-21's figures, where the check runs give them (null otherwise).
json iso_json(const BalancingCampaign& c, const CampaignAnalysis& a) {
  const IsoFigures iso = iso_figures(c, a);
  if (iso.urr.empty() && iso.umar.empty()) return nullptr;
  json urr = json::array(), umar = json::array();
  for (const auto& f : iso.urr) {
    urr.push_back(
        {{"run", f.run}, {"plane", f.plane}, {"urr", f.urr}, {"lower95", maybe(f.lower)}, {"upper95", maybe(f.upper)}});
  }
  for (const auto& f : iso.umar) {
    umar.push_back({{"plane", f.plane},
                    {"positions", f.positions},
                    {"umar", f.umar},
                    {"unit", f.unit},
                    {"lower95", maybe(f.lower)},
                    {"upper95", maybe(f.upper)}});
  }
  return {{"urr", urr}, {"umar", umar}};
}

json model_tests_json(const CampaignAnalysis& a) {
  json out = json::array();
  for (const auto& t : a.model_tests) {
    out.push_back({{"name", t.name},
                   {"ran", t.ran},
                   {"significant", t.significant},
                   {"p_value", maybe(t.p_value)},
                   {"finding", t.finding},
                   {"needs", t.needs},
                   {"residual_rms_before", maybe(t.residual_before)},
                   {"residual_rms_after", maybe(t.residual_after)},
                   {"check_rms_before", maybe(t.check_before)},
                   {"check_rms_after", maybe(t.check_after)}});
  }
  return out;
}

json speed_json(const BalancingCampaign& c, const CampaignAnalysis& a) {
  const auto& cal = a.calibration;
  json runs = json::array();
  for (const auto& r : a.runs) {
    runs.push_back({{"run", r.name},
                    {"check", r.check},
                    {"readings", r.readings},
                    {"unbalance", plane_answers_json(c, a, r.unbalance, r.applied)}});
  }
  json noise = json::array();
  for (double v : cal.noise_var) noise.push_back(std::sqrt(v));
  json out{{"campaign", c.name},
           {"amplitude_unit", c.amplitude_unit},
           {"runs_used", cal.runs},
           {"degrees_of_freedom", cal.dof},
           {"influence_coefficients", coefficients_json(c, cal)},
           {"influence_unit", c.amplitude_unit + " per g"},
           {"condition_number", cal.condition},
           {"correction", correction_json(c, a)},
           {"predicted_residual", residual_json(c, a)},
           {"predicted_residual_rms", a.correction.residual_rms},
           {"initial_unbalance", plane_answers_json(c, a, a.initial_unbalance, std::nullopt)},
           {"correction_static_couple", plane_answers_json(c, a, a.correction_masses, std::nullopt)},
           {"runs", runs},
           {"answer", a.answer},
           {"noise_sd", noise},
           {"speed_rpm", maybe(a.speed_rpm)},
           {"readings", readings_json(c, a)},
           {"model_tests", model_tests_json(a)}};
  if (json iso = iso_json(c, a); !iso.is_null()) out["iso21940_21"] = iso;
  return out;
}

json design_json(const std::vector<DesignComparison>& design) {
  json out = json::array();
  for (const auto& e : design) {
    out.push_back({{"figure", e.figure},
                   {"plane", e.plane},
                   {"output", e.output},
                   {"unit", e.unit},
                   {"real", maybe(e.real)},
                   {"share_at_or_below", e.share_below},
                   {"simulated_p2_5", e.p2_5},
                   {"simulated_p97_5", e.p97_5},
                   {"samples", e.samples},
                   {"within", e.within},
                   {"sentence", e.sentence}});
  }
  return out;
}

json calibration_json(const DesignCalibration& d) {
  json figures = json::array();
  for (const auto& f : d.figures) {
    figures.push_back({{"sensor", f.sensor},
                       {"plane", f.plane},
                       {"output", f.output},
                       {"unit", f.unit},
                       {"real", f.real},
                       {"real_se", f.real_se},
                       {"simulated_mean_before", f.before},
                       {"simulated_mean_after", f.after}});
  }
  return {{"key", d.key},
          {"unit", d.unit},
          {"value", d.value},
          {"se", d.se},
          {"range", {d.low, d.high}},
          {"at_bound", d.at_bound},
          {"chi2_before", d.chi2_before},
          {"chi2_after", d.chi2_after},
          {"dof", d.dof},
          {"evaluations", d.evaluations},
          {"figures", figures},
          {"label", "calibration"},
          {"sentence", d.sentence}};
}

}  // namespace

json analysis_json(const BalancingCampaign& c, const CampaignAnalyses& a) {
  json out = speed_json(c, a.speeds.front());
  if (a.speeds.size() > 1) {
    out["speeds"] = json::array();
    for (const auto& s : a.speeds) out["speeds"].push_back(speed_json(c, s));
  }
  out["notes"] = a.notes;
  out["design"] = design_json(a.design);
  if (a.calibration) out["calibration"] = calibration_json(*a.calibration);
  out["angle_convention"] =
      std::string("readings and influence coefficients: phase lag with each probe's angle added; masses: angles ") +
      (c.weights_with_rotation ? "with" : "against") + " rotation from the reference mark, as the campaign declares";
  return out;
}

}  // namespace poise::balancing
