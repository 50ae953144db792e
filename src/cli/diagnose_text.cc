// `poise diagnose`'s result told as the --json object and as the text report on the
// terminal, with the number and effect formatting the HTML report shares.
#include <cmath>
#include <string>

#include "cli/diagnose_output.h"
#include "core/format.h"

namespace poise::cli::diagnose_detail {
namespace est = poise::estimators;
using nlohmann::json;

namespace {

json estimate_json(const est::UnbalanceEstimate& e) {
  return {{"amplitude", e.amplitude},       {"phase_deg", e.phase * kDegPerRad},       {"offset", e.offset},
          {"se_amplitude", e.se_amplitude}, {"se_phase_deg", e.se_phase * kDegPerRad}, {"se_offset", e.se_offset}};
}

}  // namespace

std::string answer_sentence(const est::TorqueTable& t, const est::DiagnosisResult& r) {
  std::string found;
  for (const est::Effect& e : r.effects) found += (found.empty() ? "" : ", ") + effect_title(e);
  const est::UnbalanceEstimate& a = r.estimate_after;
  std::string s = (found.empty() ? "No effect beyond Eq. 22 was found in the " + std::to_string(t.size()) + " points"
                                 : "Beyond Eq. 22 the " + std::to_string(t.size()) + " points show " + found) +
                  "; the unbalance estimate is " + significant_or(a.amplitude, "n/a", 4) + " +- " +
                  significant_or(a.se_amplitude, "n/a", 2) + " " + t.unit + " at " +
                  significant_or(a.phase * kDegPerRad, "n/a", 4) + " +- " +
                  significant_or(a.se_phase * kDegPerRad, "n/a", 2) + " deg";
  if (!found.empty()) {
    s += " (the base fit alone: " + significant_or(r.estimate_before.amplitude, "n/a", 4) + " " + t.unit + " at " +
         significant_or(r.estimate_before.phase * kDegPerRad, "n/a", 4) + " deg)";
  }
  if (!r.ambiguous.empty()) {
    s += "; " + std::to_string(r.ambiguous.size()) + (r.ambiguous.size() == 1 ? " finding is" : " findings are") +
         " ambiguous on this plan (to separate: " + r.ambiguous.front().plan + ")";
  }
  s += r.omnibus.unexplained ? "; structure the candidates do not explain remains in the residual"
                             : "; no structure is left in the residual";
  return s + ".";
}

namespace {

// One found effect: its parameters, evidence, family and what it does to the estimate.
json effect_json(const est::Effect& e) {
  json params = json::object();
  for (const auto& p : e.params) params[p.name] = {{"value", p.value}, {"se", p.se}, {"unit", p.unit}};
  json j = {{"name", e.name},       {"title", effect_title(e)},   {"params", params},
            {"p_value", e.p_value}, {"p_adjusted", e.p_adjusted}, {"delta_bic", e.delta_bic},
            {"causes", e.causes}};
  if (e.name == "harmonic") j["order"] = e.order;
  // The family the issue fixes (time_drift with its shape, step, kt_drift, ...); the name
  // above stays the candidate fitted (e.g. exponential_drift: family time_drift, shape
  // exponential).
  j["family"] = e.family.empty() ? e.name : e.family;
  if (e.family == "time_drift") j["shape"] = e.shape;
  if (!e.alternative.empty()) {
    j["alternative"] = e.alternative;
    if (std::isfinite(e.shape_delta_bic)) j["alternative_delta_bic"] = e.shape_delta_bic;
  }
  if (e.name == "outlier" || e.name == "step") j["index"] = e.index, j["line"] = e.line;
  j["shift_se"] = e.shift_se;
  j["r_first_harmonic"] = e.r_first_harmonic;
  j["moves_estimate"] = e.moves_estimate;
  if (!e.estimate_note.empty()) j["estimate_note"] = e.estimate_note;
  return j;
}

// The omnibus test of the residual for structure no candidate explains, test by test.
json omnibus_json(const est::DiagnosisResult& r) {
  json omnibus = {{"p_value", r.omnibus.p_value},
                  {"unexplained_structure", r.omnibus.unexplained},
                  {"where", r.omnibus.where},
                  {"message", r.omnibus.message},
                  {"tests", json::array()}};
  for (const est::StructureTest& st : r.omnibus.tests) {
    json tj = {{"name", st.name}, {"examined", st.examined}, {"note", st.note}};
    if (st.examined) tj["statistic"] = st.statistic, tj["p_value"] = st.p_value;
    omnibus["tests"].push_back(std::move(tj));
  }
  return omnibus;
}

// Findings the data cannot decide between (each reading with its estimate and the plan that
// would separate them), the candidates' collinearity with the first harmonic, and the effects
// declared not identifiable.
json ambiguous_json(const est::DiagnosisResult& r) {
  json ambiguous = json::array();
  for (const est::AmbiguousFinding& a : r.ambiguous) {
    json readings = json::array();
    for (const est::Reading& rd : a.readings) {
      readings.push_back(
          {{"effects", rd.effects}, {"delta_bic", rd.delta_bic}, {"estimate", estimate_json(rd.estimate)}});
    }
    ambiguous.push_back({{"readings", readings}, {"correlation", a.correlation}, {"why", a.why}, {"plan", a.plan}});
  }
  return ambiguous;
}

json collinearity_json(const est::DiagnosisResult& r) {
  json collinearity = json::array();
  for (const est::CandidateCollinearity& c : r.collinearity) {
    collinearity.push_back({{"candidate", c.candidate},
                            {"r_first_harmonic", c.r_first_harmonic},
                            {"vif_base", std::isfinite(c.vif_base) ? json(c.vif_base) : json("inf")},
                            {"most_collinear_with", c.most_collinear_with},
                            {"r_other", c.r_other}});
  }
  return collinearity;
}

}  // namespace

json to_json(const est::TorqueTable& t, const est::DiagnosisResult& r, const std::optional<Load>& load, double alpha) {
  json effects = json::array();
  for (const est::Effect& e : r.effects) effects.push_back(effect_json(e));
  json not_identifiable = json::array();
  for (const auto& [name, why] : r.not_identifiable) {
    not_identifiable.push_back({{"name", name}, {"why", why}});
  }
  json out = {{"answer", answer_sentence(t, r)},
              {"file", t.file},
              {"time_column", !t.time_s.empty()},
              {"sweep_column", !t.sweep.empty()},
              {"max_harmonic", r.max_harmonic},
              {"alpha", alpha},
              {"effects", effects},
              {"rmse_before", r.rmse_before},
              {"rmse_after", r.rmse_after},
              {"estimate_before", estimate_json(r.estimate_before)},
              {"estimate_after", estimate_json(r.estimate_after)},
              {"unit", t.unit},
              {"n_points", t.size()},
              {"estimate_selected_model", estimate_json(r.estimate_selected)},
              {"plan", r.plan},
              {"omnibus", omnibus_json(r)},
              {"ambiguous", ambiguous_json(r)},
              {"collinearity", collinearity_json(r)},
              {"not_identifiable", not_identifiable},
              {"notes", r.notes},
              {"tested", r.tested}};
  if (load) {
    const est::KnownLoadErrors k = est::known_load_errors(r, load->torque, load->angle_rad);
    out["load"] = {{"torque", load->torque}, {"angle_deg", load->angle_rad * kDegPerRad}};
    out["error_before"] = {{"amplitude", k.before.amplitude}, {"phase_deg", k.before.phase_deg}};
    out["error_after"] = {{"amplitude", k.after.amplitude}, {"phase_deg", k.after.phase_deg}};
  }
  return out;
}

std::string params_text(const est::Effect& e, const std::string& sep) {
  std::string s;
  for (const auto& p : e.params) {
    s += (s.empty() ? "" : sep) + p.name + " = " + significant_or(p.value, "n/a") + " +- " +
         significant_or(p.se, "n/a", 2) + (p.unit.empty() ? "" : " " + p.unit);
  }
  return s;
}

std::string effect_title(const est::Effect& e) {
  if (e.name == "harmonic") return "harmonic " + std::to_string(e.order);
  if (e.family == "time_drift" && e.shape == "not identifiable") {
    return "time effect; shape not identifiable (fitted as " + e.name +
           (e.alternative.empty() ? "" : "; or " + e.alternative) + ")";
  }
  if (e.family == "time_drift") return "time_drift (" + e.shape + ")";
  if (e.name == "outlier") {
    return "outlier at row " + std::to_string(e.index) + " (file line " + std::to_string(e.line) + ")";
  }
  if (e.name == "step") {
    return "step before row " + std::to_string(e.index) + " (file line " + std::to_string(e.line) + ")";
  }
  return e.name;
}

std::string estimate_text(const est::UnbalanceEstimate& e, const std::string& u) {
  return "amplitude " + significant_or(e.amplitude, "n/a", 5) + " +- " + significant_or(e.se_amplitude, "n/a", 2) +
         " " + u + ", phase " + significant_or(e.phase * kDegPerRad, "n/a", 5) + " +- " +
         significant_or(e.se_phase * kDegPerRad, "n/a", 2) + " deg, offset " + significant_or(e.offset, "n/a", 4) +
         " +- " + significant_or(e.se_offset, "n/a", 2) + " " + u;
}

namespace {

std::string error_text(const est::EstimateError& e, const std::string& u) {
  return "amplitude " + significant_or(e.amplitude, "n/a", 3) + " " + u + ", phase " +
         significant_or(e.phase_deg, "n/a", 3) + " deg, unbalance left after correction " +
         significant_or(e.vector, "n/a", 3) + " " + u;
}

}  // namespace

void print_text(const est::TorqueTable& t, const est::DiagnosisResult& r, double alpha, const std::optional<Load>& load,
                std::ostream& out) {
  const std::string& u = t.unit;
  const auto& b = r.estimate_before;
  out << "Residual diagnosis of " << t.size() << " points from " << t.file << " (torque in " << u
      << "; time: " << (t.time_s.empty() ? "row order" : "column time_s")
      << "; sweep: " << (t.sweep.empty() ? "none" : "column sweep") << ")\n"
      << "Searched: harmonics 2.." << r.max_harmonic
      << ", time drift, K_T drift, direction offset, step, exponential settling, outliers, AR(1) "
         "errors; forward stepwise, Holm per round at alpha = "
      << alpha << ", delta_BIC < 0\n\n"
      << "Base fit (Eq. 22): M(theta) = " << significant_or(b.amplitude, "n/a", 5) << " sin(theta + "
      << significant_or(b.phase * kDegPerRad, "n/a", 4) << " deg) + " << significant_or(b.offset, "n/a", 4) << " " << u
      << "\n\n";
  out << "Effects found (in the order added):" << (r.effects.empty() ? " none\n" : "\n");
  for (std::size_t i = 0; i < r.effects.size(); ++i) {
    const est::Effect& e = r.effects[i];
    out << "  " << i + 1 << ". " << effect_title(e) << ": " << params_text(e, ", ") << "\n"
        << "     p = " << significant_or(e.p_value, "n/a", 3)
        << ", Holm-adjusted p = " << significant_or(e.p_adjusted, "n/a", 3)
        << ", delta_BIC = " << significant_or(e.delta_bic, "n/a", 3) << "\n"
        << "     causes: " << e.causes << "\n"
        << "     moves the unbalance estimate by " << significant_or(e.shift_se, "n/a", 3)
        << " SE; trades off with the first harmonic at r = " << significant_or(e.r_first_harmonic, "n/a", 3)
        << (e.moves_estimate ? "" : "; " + e.estimate_note) << "\n";
  }
  for (const auto& s : r.notes) out << "  note: " << s << "\n";
  out << "\nPlan: " << r.plan << "\n"
      << "Collinearity under this plan (r1: canonical correlation with the first harmonic; VIF "
         "against Eq. 22; the closest other candidate, base projected out; limit 0.9):\n";
  for (const est::CandidateCollinearity& c : r.collinearity) {
    out << "  " << c.candidate << ": r1 " << significant_or(c.r_first_harmonic, "n/a", 3) << ", VIF "
        << significant_or(c.vif_base, "n/a", 3)
        << (c.most_collinear_with.empty()
                ? ""
                : ", closest " + c.most_collinear_with + " at r " + significant_or(c.r_other, "n/a", 3))
        << (c.r_other >= 0.9 || c.r_first_harmonic >= 0.9 || c.vif_base >= 1.0 / (1.0 - 0.81)
                ? "  (not separable on this plan)"
                : "")
        << "\n";
  }
  for (std::size_t i = 0; i < r.ambiguous.size(); ++i) {
    const est::AmbiguousFinding& a = r.ambiguous[i];
    out << "Ambiguous finding " << i + 1 << ": " << a.why << "\n";
    for (const est::Reading& rd : a.readings) {
      out << "  reading " << rd.effects << " (delta_BIC " << significant_or(rd.delta_bic, "n/a", 3)
          << "): " << estimate_text(rd.estimate, u) << "\n";
    }
    out << "  a plan that would separate them: " << a.plan << "\n";
  }
  out << "\nOmnibus check of the final residual: " << r.omnibus.message << "\n";
  for (const est::StructureTest& st : r.omnibus.tests) {
    out << "  " << st.name << ": "
        << (st.examined ? "statistic " + significant_or(st.statistic, "n/a", 4) + ", p = " +
                              significant_or(st.p_value, "n/a", 3) + (st.note.empty() ? "" : " (" + st.note + ")")
                        : st.note)
        << "\n";
  }
  for (const auto& [name, why] : r.not_identifiable) {
    out << "Not identifiable from one test: " << name << ": " << why << "\n";
  }
  out << "\nCandidates tested in the last round, not added:\n";
  for (const auto& s : r.tested) out << "  " << s << "\n";
  out << "\nrmse (sqrt(RSS/n)): before " << significant_or(r.rmse_before, "n/a") << " " << u << ", after "
      << significant_or(r.rmse_after, "n/a") << " " << u << "\n"
      << "Unbalance estimate (first harmonic, +- 1 SE):\n"
      << "  before: " << estimate_text(r.estimate_before, u) << "\n"
      << "  selected model: " << estimate_text(r.estimate_selected, u) << "\n"
      << "  after:  " << estimate_text(r.estimate_after, u) << " (the estimate reported: see the effects' notes)\n";
  if (load) {
    const est::KnownLoadErrors k = est::known_load_errors(r, load->torque, load->angle_rad);
    out << "Error against the known load " << significant_or(load->torque, "n/a") << " " << u << " at "
        << significant_or(load->angle_rad * kDegPerRad, "n/a") << " deg (estimate - load):\n"
        << "  before: " << error_text(k.before, u) << "\n"
        << "  after:  " << error_text(k.after, u) << "\n";
  }
}

}  // namespace poise::cli::diagnose_detail
