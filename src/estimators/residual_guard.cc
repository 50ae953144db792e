#include "estimators/residual_guard.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/angles.h"
#include "core/format.h"
#include "estimators/residual_effects.h"

namespace poise::estimators::detail {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

Vector3d coefficients(const UnbalanceEstimate& e) {
  return {e.amplitude * std::cos(e.phase), e.amplitude * std::sin(e.phase), e.offset};
}

// The effect's own test once AR(1) errors are allowed: its drop-one F test (GLS, Bonferroni
// over a scanned family's members) in the model with AR(1) errors, at the REML rho of that
// model and at the upper end of rho's 95 % profile interval (l_R within 1.92 of its maximum):
// with the effect in, rho is estimated low when the effect fits a wander of the noise, so the
// effect must hold at every larger rho the data accept. The larger p of the two.
double p_under_ar1(const Model& m, const ModelData& d, std::size_t i) {
  constexpr double kHalfChi2 = 1.92;  // chi^2(1) 95 % / 2
  constexpr double kStep = 0.01;      // the rho grid's step, up to kMaxRho (residual_diagnosis_model.h)
  Model g = m;
  g.ar = true;
  g.rho = fit_rho(g.x, d);
  double upper = g.rho.rho;
  while (upper + kStep <= kMaxRho && restricted_loglik(g.x, d, upper + kStep) > g.rho.loglik - kHalfChi2) {
    upper += kStep;
  }
  const int family = std::max(1, m.terms[i].scanned);
  double p = drop_one_p(g, d, i);
  g.rho.rho = upper;
  p = std::max(p, drop_one_p(g, d, i));
  return std::min(1.0, p * family);
}

// Whether the data tell term i of m from candidate c (each tested given the other in the
// model with both, Bonferroni over a scanned family: Cox/Davidson-MacKinnon encompassing):
// true when term i holds beyond doubt given c (p < kIdentifiedP: the guard only asks when
// their estimates differ beyond kGuardSe, a move that needs an identified effect) and c does
// not hold at alpha given term i.
bool separated(const Model& m, const ModelData& d, std::size_t i, const Term& c, double alpha) {
  const Model joint = with_term(m, d, c);
  const LinearFit f = fit_linear(joint.x, d, joint.ar, joint.rho.rho);
  if (!f.ok) return false;  // the same columns: nothing tells them apart
  const double p_t = drop_one_p(joint, d, i) * std::max(1, m.terms[i].scanned);
  const double p_c = drop_one_p(joint, d, joint.terms.size() - 1) * std::max(1, c.scanned);
  return p_t < kIdentifiedP && !(p_c < alpha);
}

struct Competitor {
  Reading reading;
  std::string name;           // candidate name, for the separating plan
  bool noise_wander = false;  // the effect not told from correlated noise
};

// The competing explanations of term i (the guard's list in residual_guard.h).
std::vector<Competitor> competitors(const Model& m, const GuardInputs& in, std::size_t i, double r_first, bool moves) {
  const ModelData& d = in.d;
  const Term& t = m.terms[i];
  const double bic_sel = model_bic(m, d);
  Model rest = without_term(m, i);
  if (rest.ar) rest.rho = fit_rho(rest.x, d);
  std::vector<Competitor> out;
  for (const Term& c : in.pool(rest)) {
    if (c.name == t.name && c.order == t.order) continue;
    const Model alt = with_term(rest, d, c);
    const double db = model_bic(alt, d) - bic_sel;
    if (db < kBicVeryStrong && !separated(m, d, i, c, in.alpha)) {
      out.push_back({{term_label(c), db, estimate_of(alt, d)}, c.name});
    }
  }
  if (!m.ar) {
    const Model alt = with_term(rest, d, Term("autocorrelation", "autocorrelation"));
    const double db = model_bic(alt, d) - bic_sel;
    // On a one-direction sweep a time-shaped effect that trades off with the first harmonic
    // or moves the estimate beyond kGuardSe must pass its test with AR(1) errors allowed: at
    // alpha, or at kIdentifiedP when r >= kFirstHarmonicLimit or it moves the estimate
    // beyond kGuardSe (as without AR). (A harmonic
    // there has AR(1) errors as a reading already: residual_assessment.h.)
    const double level = r_first >= kFirstHarmonicLimit || moves ? kIdentifiedP : in.alpha;
    const bool inseparable = in.monotone_plan && is_time_like(t.name) && (r_first >= kWeakCorrelation || moves) &&
                             p_under_ar1(m, d, i) >= level;
    if (db < kBicVeryStrong || inseparable) {
      out.push_back({{"autocorrelation (AR(1) errors) instead of " + term_label(t) +
                          (inseparable ? " (with AR(1) errors allowed its own test fails)" : ""),
                      db, estimate_of(alt, d)},
                     "autocorrelation",
                     inseparable});
    }
  }
  return out;
}

// Canonical correlation of term i's columns with (sin, cos) given the rest of the model.
double first_harmonic_tradeoff(const Model& m, const ModelData& d, std::size_t i) {
  const Model rest = without_term(m, i);
  Eigen::MatrixXd others(d.n, rest.x.cols() - 2);
  others << rest.x.col(2), rest.x.rightCols(rest.x.cols() - 3);
  return canonical_correlation(residualize(m.terms[i].cols, others), residualize(m.x.leftCols(2), others));
}

}  // namespace

std::string separating_plan(const std::string& a, const std::string& b) {
  const bool ha = a.rfind("harmonic", 0) == 0, hb = b.rfind("harmonic", 0) == 0;
  const bool ta = is_time_like(a), tb = is_time_like(b);
  const bool da = a == "direction_offset", db = b == "direction_offset";
  if ((ha && tb) || (hb && ta)) {
    return "randomise or interleave the position order (e.g. 0, 180, 90, 270, 45, 225, ... deg) so "
           "that time no longer follows angle, or repeat the sweep in the opposite direction; "
           "repeat a few positions at the end of the run";
  }
  if (a == "autocorrelation" || b == "autocorrelation") {
    return "repeat the sweep, in the opposite direction or in a shuffled order: a deterministic "
           "effect comes back where it was, a wander of correlated noise does not";
  }
  if ((a == "kt_drift" && b != "kt_drift") || (b == "kt_drift" && a != "kt_drift")) {
    return "repeat the test with a second known load (a K_T drift scales with the torque, an "
           "additive effect does not), or reverse the sweep so that time no longer follows angle";
  }
  if ((da && tb) || (db && ta)) {
    return "a back-and-forth sweep with the directions interleaved (+ - + - ... or both "
           "directions at every position), so that the direction does not follow time";
  }
  if (a == "first harmonic" || b == "first harmonic") {
    return "cover the whole turn evenly, in a randomised order, and repeat some positions at the "
           "start and end of the run";
  }
  if (ha && hb) return "cover the whole turn evenly: harmonics are then orthogonal";
  if (ta && tb) {
    return "a longer run, or repeated positions spread over the run (a step, a settling and a "
           "drift differ in shape only over enough time)";
  }
  return "repeat positions at the start and end of the run and randomise the position order";
}

namespace {

// m without the terms flagged in `drop`.
Model without_terms(const Model& m, const ModelData& d, const std::vector<bool>& drop) {
  Model out = m;
  for (std::size_t i = m.terms.size(); i-- > 0;) {
    if (drop[i]) out = without_term(out, i);
  }
  if (out.ar) out.rho = fit_rho(out.x, d);
  return out;
}

// The readings of term j of cur (cur: the selected model without the terms guarded so far)
// against the plain estimate; an ambiguous finding when one disagrees beyond kGuardSe.
bool guard_one(const Model& cur, const GuardInputs& in, std::size_t j, DiagnosisResult& res, double& allowance,
               CompetingReading& competing) {
  const ModelData& d = in.d;
  const LinearFit f = fit_linear(cur.x, d, cur.ar, cur.rho.rho);
  if (!f.ok) return false;
  const Eigen::Matrix2d cov = f.cov.block<2, 2>(0, 0);
  const UnbalanceEstimate sel_est = estimate_of(cur, d);
  const Vector3d sel = coefficients(sel_est);
  const double r_first = first_harmonic_tradeoff(cur, d, j);
  Model rest = without_term(cur, j);
  if (rest.ar) rest.rho = fit_rho(rest.x, d);
  const Vector3d plain = coefficients(estimate_of(rest, d));
  const auto se_apart = [&](const Vector3d& x, const Vector3d& y) {
    const Vector2d diff = x.head<2>() - y.head<2>();
    const double len = diff.norm();
    if (!(len > 0.0)) return 0.0;
    const double se = std::sqrt(std::max(0.0, (diff / len).dot(cov * (diff / len))));
    return se > 0.0 ? len / se : std::numeric_limits<double>::infinity();
  };
  const auto n_se = [&](const Vector3d& x) { return se_apart(x, sel); };
  const std::vector<Competitor> comp = competitors(cur, in, j, r_first, n_se(plain) > kGuardSe);
  double worst_se = 0.0, reach = (sel - plain).head<2>().norm();
  const Competitor* against = nullptr;
  // A competing explanation that leaves the estimate where the plain fit has it (within
  // kGuardSe) while the selected effect moves it beyond kGuardSe: the move is not earned.
  // (When every competitor moves the estimate away from the plain value too, the readings
  // are averaged by assess() instead.)
  for (const Competitor& c : comp) {
    const Vector3d x = coefficients(c.reading.estimate);
    const double apart = n_se(x);
    const bool keeps_plain = c.noise_wander || se_apart(x, plain) <= kGuardSe;
    if (apart > kGuardSe && keeps_plain && apart > worst_se) {
      worst_se = apart, against = &c;
    }
  }
  // Moving the estimate beyond kGuardSe takes an effect identified beyond doubt: drop-one
  // p < kIdentifiedP (Bonferroni over a scanned family), else "no effect" is a reading.
  const Competitor none{{"no effect", model_bic(rest, d) - model_bic(cur, d), estimate_of(rest, d)}, "first harmonic"};
  const double p_own = drop_one_p(cur, d, j) * std::max(1, cur.terms[j].scanned);
  if (n_se(plain) > kGuardSe && p_own >= kIdentifiedP && n_se(plain) > worst_se) {
    worst_se = n_se(plain), against = &none;
  }
  if (against == nullptr) return false;
  const std::string name = term_label(cur.terms[j]);
  AmbiguousFinding a;
  a.readings.push_back({name, 0.0, sel_est});
  for (const Competitor& c : comp) {
    a.readings.push_back(c.reading);
    reach = std::max(reach, (coefficients(c.reading.estimate) - plain).head<2>().norm());
  }
  a.readings.push_back(
      {"plain estimate (without " + name + ")", model_bic(rest, d) - model_bic(cur, d), estimate_of(rest, d)});
  a.why = fmt::format(
      "{} and {} fit the data about as well (BIC within 10, or not separable from "
      "correlated noise) and give unbalance estimates {:.1f} SE apart",
      name, against->reading.effects, worst_se);
  a.why += in.monotone_plan ? "; time order follows angle order" : "";
  a.correlation = r_first;
  a.plan = separating_plan(cur.terms[j].name, against->name);
  allowance = 0.25 * reach * reach;
  competing = {against->reading.effects, against->name};
  res.ambiguous.push_back(std::move(a));
  return true;
}

}  // namespace

GuardResult guard_estimate(const Model& m, const GuardInputs& in, DiagnosisResult& res) {
  GuardResult g;
  g.allowance.assign(m.terms.size(), std::numeric_limits<double>::quiet_NaN());
  g.against.assign(m.terms.size(), {});
  std::vector<bool> drop(m.terms.size(), false);
  for (std::size_t i = 0; i < m.terms.size(); ++i) {
    if (m.terms[i].name == "autocorrelation") continue;
    const Model cur = without_terms(m, in.d, drop);
    std::size_t j = i;  // index of term i in cur
    for (std::size_t k = 0; k < i; ++k) j -= drop[k] ? 1 : 0;
    double a = 0.0;
    if (!guard_one(cur, in, j, res, a, g.against[i])) continue;
    drop[i] = true;
    g.allowance[i] = a;
    res.effects[i].estimate_note =
        "a competing explanation the data do not separate leaves the estimate where the plain "
        "fit has it, more than 2 SE from this effect's: the estimate keeps the plain value for "
        "this effect, its uncertainty widened to span every reading";
  }
  return g;
}

namespace {

bool shape_or_direction(const std::string& n) {
  return n == "time_drift" || n == "exponential_drift" || n == "step" || n == "kt_drift" || n == "direction_offset" ||
         n == "time_drift_quadratic";
}

std::string family_of(const std::string& name) {
  if (name == "time_drift" || name == "time_drift_quadratic" || name == "exponential_drift") {
    return "time_drift";
  }
  return name;
}

std::string shape_of(const std::string& name) {
  if (name == "time_drift") return "linear";
  if (name == "exponential_drift") return "exponential";
  if (name == "time_drift_quadratic") return "not identifiable";
  return "";
}

// BIC lead that identifies shape a against b: 2 within the additive time family (drift,
// settling, step: "positive" evidence, Kass and Raftery 1995), 6 across families (a direction
// offset, or the multiplicative K_T drift, against an additive time effect: "strong"), whose
// corrections differ in kind and which the usual plans confound.
double identified_by(const std::string& a, const std::string& b) {
  const auto additive = [](const std::string& n) {
    return n == "time_drift" || n == "exponential_drift" || n == "step" || n == "time_drift_quadratic";
  };
  return additive(a) && additive(b) ? kBicIndistinct : kBicStrong;
}

}  // namespace

void name_families(const Model& m, const ModelData& d, const CandidatePool& pool, const GuardResult& guard,
                   DiagnosisResult& res) {
  const bool curved = m.has("time_drift_quadratic");
  for (std::size_t i = 0; i < m.terms.size(); ++i) {
    const Term& t = m.terms[i];
    Effect& e = res.effects[i];
    e.family = family_of(t.name);
    e.shape = curved && e.family == "time_drift" ? "not identifiable" : shape_of(t.name);
    if (!shape_or_direction(t.name)) continue;
    const double bic_sel = model_bic(m, d);
    Model rest = without_term(m, i);
    if (rest.ar) rest.rho = fit_rho(rest.x, d);
    double best = std::numeric_limits<double>::infinity();  // BIC margin left, least first
    std::string alternative_name;
    for (const Term& c : pool(rest)) {
      if (c.name == t.name || !shape_or_direction(c.name) || c.name == "time_drift_quadratic") {
        continue;
      }
      const double db = model_bic(with_term(rest, d, c), d) - bic_sel;
      if (db - identified_by(t.name, c.name) < best) {
        best = db - identified_by(t.name, c.name);
        e.shape_delta_bic = db, e.alternative = term_label(c), alternative_name = c.name;
      }
    }
    if (t.name == "direction_offset") continue;
    std::string other;  // the reading the shape is not told from
    if (e.shape_delta_bic < identified_by(t.name, alternative_name)) {
      e.family = "time_drift";
      e.shape = "not identifiable";
      other = alternative_name;
    }
    if (i < guard.against.size() && !guard.against[i].label.empty()) {
      e.family = "time_drift";
      e.shape = "not identifiable";
      e.alternative = guard.against[i].label;
      other = guard.against[i].name;
    }
    // Its causes are those of either reading (not of a harmonic, whose order is not kept here).
    if (!other.empty() && other != t.name && other != "first harmonic" && other != "harmonic") {
      e.causes += " Or, read as " + other + ": " + causes_of(other, 0);
    }
  }
}

}  // namespace poise::estimators::detail
