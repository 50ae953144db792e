#include "estimators/residual_assessment.h"

#include <algorithm>
#include <cmath>

#include "core/angles.h"
#include "core/format.h"

namespace poise::estimators::detail {
namespace {

using angles::wrap_two_pi;
using Eigen::MatrixXd;

// (a, c, K) of the model.
Eigen::Vector3d coefficients(const Model& m, const ModelData& d) {
  const UnbalanceEstimate e = estimate_of(m, d);
  return {e.amplitude * std::cos(e.phase), e.amplitude * std::sin(e.phase), e.offset};
}

// Bayesian model averaging over the readings with BIC weights w_i ~ exp(-delta_BIC_i / 2)
// (Raftery 1995): the mean's move from the selected model goes into delta, the between-
// readings variance sum w_i |x_i - mean|^2 (first harmonic) into allowance2.
void average_readings(const AmbiguousFinding& a, const Eigen::Vector3d& coef_sel, Eigen::Vector3d& delta,
                      double& allowance2, bool equal_weights = false) {
  double wsum = 0.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::vector<std::pair<double, Eigen::Vector3d>> v;
  for (const Reading& r : a.readings) {
    const double w = equal_weights ? 1.0 : std::exp(-0.5 * std::max(r.delta_bic, -50.0));
    const Eigen::Vector3d x(r.estimate.amplitude * std::cos(r.estimate.phase),
                            r.estimate.amplitude * std::sin(r.estimate.phase), r.estimate.offset);
    v.emplace_back(w, x);
    wsum += w;
    mean += w * x;
  }
  mean /= wsum;
  double between = 0.0;
  for (const auto& [w, x] : v) between += w / wsum * (x.head<2>() - mean.head<2>()).squaredNorm();
  delta += mean - coef_sel;
  allowance2 += between;
}

// What the assessment of the selected model works from, and the move it accumulates: delta
// (a, c, K) from the selected model's estimate and allowance2, the variance added to the
// estimate's (table unit^2), from the readings' spread.
struct Assessment {
  Assessment(const Model& model, const AssessmentInputs& inputs)
      : m(model),
        in(inputs),
        d(inputs.d),
        bic_sel(model_bic(model, inputs.d)),
        coef_sel(coefficients(model, inputs.d)) {
    const LinearFit f = fit_linear(m.x, d, m.ar, m.rho.rho);
    cov_sel = f.cov.block<2, 2>(0, 0);
  }
  const Model& m;
  const AssessmentInputs& in;
  const ModelData& d;
  double bic_sel;
  Eigen::Vector3d coef_sel;
  Eigen::Matrix2d cov_sel;
  Eigen::Vector3d delta = Eigen::Vector3d::Zero();
  double allowance2 = 0.0;
  bool guarded_any = false;
};

// The readings of one term: every candidate of the pool on the rest of the model that the
// design or the data cannot tell from this effect.
struct TermReadings {
  AmbiguousFinding finding;
  std::string other_name;
  bool shape_readings = false;  // a time shape the data do not reject very strongly
};

TermReadings readings_of_term(const Assessment& s, std::size_t i, const Model& rest, const Effect& e) {
  const Model& m = s.m;
  const ModelData& d = s.d;
  const Term& t = m.terms[i];
  TermReadings out;
  AmbiguousFinding& a = out.finding;
  a.readings.push_back({term_label(t), 0.0, estimate_of(m, d)});
  const MatrixXd te = residualize(t.cols, rest.x);
  for (const Term& c : s.in.pool(rest)) {
    if (c.name == t.name && c.order == t.order) continue;
    if (!c.examined && c.cols.cols() == 0) continue;
    const double r = canonical_correlation(te, residualize(c.cols, rest.x));
    if (r < kWeakCorrelation) continue;
    const Model alt = with_term(rest, d, c);
    const double db = model_bic(alt, d) - s.bic_sel;
    // Occam's window for a time shape that trades off with the unbalance (r >= 0.5 with
    // the first harmonic): which shape holds decides the estimate, so every other time
    // shape the data do not reject very strongly (BIC within 10, Kass and Raftery 1995) is
    // a reading, and the readings count equally: a K_T drift read as a step or as a linear
    // drift moved the estimate 4-7 SE the wrong way in 7 of 100 independent tables.
    const bool shape_window =
        is_time_like(t.name) && is_time_like(c.name) && e.r_first_harmonic >= kWeakCorrelation && db < kBicVeryStrong;
    out.shape_readings = out.shape_readings || (shape_window && db >= kBicIndistinct);
    if ((r >= kConfounded && db < kBicStrong) || db < kBicIndistinct || shape_window) {
      a.readings.push_back({term_label(c), db, estimate_of(alt, d)});
      if (r > a.correlation) a.correlation = r, out.other_name = c.name;
    }
  }
  // A time-shaped effect that trades off with the unbalance against correlated noise in
  // its place: a wander of AR(1) noise holds steps and drifts, and the BIC weights decide.
  if (!m.ar && is_time_like(t.name) && e.r_first_harmonic >= kWeakCorrelation) {
    const Model alt = with_term(rest, d, Term("autocorrelation", "autocorrelation"));
    const double db = model_bic(alt, d) - s.bic_sel;
    if (db < kBicStrong) {
      a.readings.push_back({"autocorrelation (AR(1) errors) instead of " + term_label(t), db, estimate_of(alt, d)});
      if (out.other_name.empty()) out.other_name = "autocorrelation";
    }
  }
  return out;
}

// (a, c) of a reading's estimate.
Eigen::Vector2d first_harmonic(const Reading& r) {
  return {r.estimate.amplitude * std::cos(r.estimate.phase), r.estimate.amplitude * std::sin(r.estimate.phase)};
}

// Whether some reading's first harmonic lies beyond 2 SE of the selected model's, along the
// line between them (the selected estimate's covariance).
bool readings_disagree(const Assessment& s, const AmbiguousFinding& a) {
  for (const Reading& r : a.readings) {
    const Eigen::Vector2d v = first_harmonic(r) - s.coef_sel.head<2>();
    const double len = v.norm();
    if (!(len > 0.0)) continue;
    const Eigen::Vector2d u = v / len;
    if (len > 2.0 * std::sqrt(std::max(0.0, u.dot(s.cov_sel * u)))) return true;
  }
  return false;
}

// The estimate without the term, with the readings' spread about it (half the largest
// distance, as a standard deviation) added: a term not identified against the first harmonic,
// or readings that disagree and that the data do not separate.
void keep_plain_estimate(Assessment& s, const AmbiguousFinding& a, const Eigen::Vector3d& coef_rest) {
  double spread = 0.0;
  for (const Reading& r : a.readings) spread = std::max(spread, (first_harmonic(r) - coef_rest.head<2>()).norm());
  s.delta += coef_rest - s.coef_sel;
  s.allowance2 += 0.25 * spread * spread;
}

// An ambiguous term: the estimate does not take it alone. Against the first harmonic (not
// identified), the readings' spread goes into the uncertainty; otherwise the readings are
// averaged (BIC weights, or equally across time shapes).
void settle_ambiguous_term(Assessment& s, std::size_t i, const Eigen::Vector3d& coef_rest, bool harmonic_confounded,
                           TermReadings&& tr, Effect& e, DiagnosisResult& res) {
  const Term& t = s.m.terms[i];
  AmbiguousFinding& a = tr.finding;
  e.moves_estimate = false;
  a.why =
      term_label(t) + " and " + a.readings[1].effects +
      (a.correlation > 0.0 ? fmt::format(" are collinear under this plan (canonical correlation {:.3f})", a.correlation)
                           : std::string(" are not told apart by these data (BIC within 6)")) +
      (s.in.monotone_plan ? "; time order follows angle order" : "");
  a.plan = separating_plan(t.name == "harmonic" ? "harmonic" : t.name,
                           tr.other_name == "harmonic" ? "harmonic" : tr.other_name);
  if (harmonic_confounded) {
    keep_plain_estimate(s, a, coef_rest);
    e.estimate_note =
        "trades off with the first harmonic and is not identified (drop-one p >= "
        "1e-4): the estimate does not take it; the readings' spread is added to "
        "its uncertainty";
  } else if (!tr.shape_readings && e.shift_se < 1.0 && readings_disagree(s, a)) {
    // The effect found hardly moves the estimate, a reading the data do not separate from it
    // would move it beyond 2 SE: only that reading argues for the move, and the data do not
    // favour it; the estimate stays where the plain fit has it.
    keep_plain_estimate(s, a, coef_rest);
    e.estimate_note =
        "ambiguous: this effect moves the estimate by less than 1 SE, and a reading the data do not "
        "separate from it would move it by more than 2 SE: the estimate keeps the value without it, the "
        "readings' spread added to its uncertainty";
  } else {
    average_readings(a, s.coef_sel, s.delta, s.allowance2, tr.shape_readings);
    e.estimate_note = tr.shape_readings
                          ? "the time shape trades off with the unbalance and the data do not single it out "
                            "(another shape within 10 BIC): the estimate averages the readings equally, their "
                            "spread added to its uncertainty"
                          : "ambiguous: the estimate averages the readings with BIC weights, their spread "
                            "added to its uncertainty";
  }
  res.ambiguous.push_back(std::move(a));
}

// One term of the selected model: its shift of the estimate in standard errors, its trade-off
// with the first harmonic, and whether the estimate takes it (guarded, ambiguous, a tentative
// outlier in correlated noise, or identified).
void assess_term(Assessment& s, std::size_t i, DiagnosisResult& res) {
  const Model& m = s.m;
  const ModelData& d = s.d;
  const Term& t = m.terms[i];
  Effect& e = res.effects[i];
  const Model rest = without_term(m, i);
  const Eigen::Vector3d coef_rest = coefficients(rest, d);
  const Eigen::Vector2d mv = s.coef_sel.head<2>() - coef_rest.head<2>();
  const double len = mv.norm();
  if (len > 0.0 && std::isfinite(len)) {
    const Eigen::Vector2d u = mv / len;
    const double se = std::sqrt(std::max(0.0, u.dot(s.cov_sel * u)));
    e.shift_se = se > 0.0 ? len / se : std::numeric_limits<double>::infinity();
  }
  if (t.name == "autocorrelation") return;  // changes weights, not columns
  // Trade-off with the first harmonic given the rest of the model (constant kept).
  MatrixXd others(d.n, rest.x.cols() - 2);
  others << rest.x.col(2), rest.x.rightCols(rest.x.cols() - 3);
  e.r_first_harmonic = canonical_correlation(residualize(t.cols, others), residualize(m.x.leftCols(2), others));
  if (s.in.guarded != nullptr && std::isfinite((*s.in.guarded)[i])) {
    e.moves_estimate = false;  // the guard keeps the plain estimate (residual_guard.h)
    s.guarded_any = true;
    s.allowance2 += (*s.in.guarded)[i];
    return;
  }
  TermReadings tr = readings_of_term(s, i, rest, e);
  const bool harmonic_confounded = e.r_first_harmonic >= kFirstHarmonicLimit && drop_one_p(m, d, i) >= kIdentifiedP;
  if (harmonic_confounded) {
    tr.finding.readings.push_back(
        {"no effect (part of the first harmonic)", model_bic(rest, d) - s.bic_sel, estimate_of(rest, d)});
    tr.finding.correlation = std::max(tr.finding.correlation, e.r_first_harmonic);
    if (tr.other_name.empty()) tr.other_name = "first harmonic";
  }
  if (tr.finding.readings.size() > 1) {
    settle_ambiguous_term(s, i, coef_rest, harmonic_confounded, std::move(tr), e, res);
  } else if (t.name == "outlier" && (s.in.residual_correlated || m.ar)) {
    e.moves_estimate = false;
    s.delta += coef_rest - s.coef_sel;
    s.allowance2 += 0.25 * mv.squaredNorm();
    e.estimate_note =
        "in correlated noise a single excursion is not told from the noise's own: "
        "tentative, the estimate does not take it";
  }
}

// The guarded effects dropped together: a term collinear with another moves the estimate
// far when dropped alone, and such moves do not add.
void drop_guarded_terms_together(Assessment& s) {
  Model plain = s.m;
  for (std::size_t i = s.m.terms.size(); i-- > 0;) {
    if (std::isfinite((*s.in.guarded)[i])) plain = without_term(plain, i);
  }
  if (plain.ar) plain.rho = fit_rho(plain.x, s.d);
  s.delta += coefficients(plain, s.d) - s.coef_sel;
}

// On a plan where time follows angle, the harmonics found (together) against AR(1) errors
// in their place: a smooth function of angle is then a smooth function of time, and only a
// repeated or reordered sweep tells a deterministic harmonic from correlated noise.
void weigh_harmonics_against_correlated_noise(Assessment& s, DiagnosisResult& res) {
  const Model& m = s.m;
  Model alt = m;
  std::string names;
  std::vector<std::size_t> members;
  for (std::size_t i = m.terms.size(); i-- > 0;) {
    if (m.terms[i].name != "harmonic" || !res.effects[i].moves_estimate) continue;
    names = m.terms[i].label + (names.empty() ? "" : ", " + names);
    members.push_back(i);
    alt = without_term(alt, i);
  }
  if (members.empty()) return;
  alt = with_term(alt, s.d, Term("autocorrelation", "autocorrelation"));
  const double db = model_bic(alt, s.d) - s.bic_sel;
  AmbiguousFinding a;
  a.readings.push_back({names, 0.0, estimate_of(m, s.d)});
  a.readings.push_back({"autocorrelation (AR(1) errors) instead of " + names, db, estimate_of(alt, s.d)});
  a.correlation = 1.0;
  a.why = names +
          " and correlated noise: time order follows angle order, so a smooth "
          "function of angle is one of time; whatever the BIC says, it rests on "
          "the AR(1) form of the noise, which the plan cannot check";
  a.plan = separating_plan("harmonic", "autocorrelation");
  average_readings(a, s.coef_sel, s.delta, s.allowance2);
  for (std::size_t i : members) {
    res.effects[i].moves_estimate = false;
    res.effects[i].estimate_note =
        "ambiguous with correlated noise on this plan: the estimate averages the two "
        "readings with BIC weights, their spread added to its uncertainty";
  }
  res.ambiguous.push_back(std::move(a));
}

// The two searches (AR(1) allowed first, AR(1) deferred) ended in different models on a plan
// where time follows angle: correlated noise against time-shaped effects rests on the AR(1)
// form of the noise, which this plan cannot check; both readings count equally.
void weigh_the_other_search(Assessment& s, DiagnosisResult& res) {
  const Model& m = s.m;
  const Model& o = *s.in.other_search;
  bool open = false;  // an effect of the selected model not in the other one still moves
  for (std::size_t i = 0; i < m.terms.size(); ++i) {
    const bool shared = std::any_of(o.terms.begin(), o.terms.end(), [&](const Term& x) {
      return x.name == m.terms[i].name && x.order == m.terms[i].order;
    });
    if (!shared && res.effects[i].moves_estimate) open = true;
  }
  if (!open) return;
  AmbiguousFinding a;
  a.readings.push_back({s.in.selected_summary, 0.0, estimate_of(m, s.d)});
  a.readings.push_back({s.in.other_summary, model_bic(o, s.d) - s.bic_sel, estimate_of(o, s.d)});
  a.correlation = 1.0;
  a.why = s.in.selected_summary + " and " + s.in.other_summary +
          ": the search ends in either, and time order follows angle order, so which one "
          "holds rests on the AR(1) form of the noise, which the plan cannot check";
  a.plan = separating_plan("harmonic", "autocorrelation");
  average_readings(a, s.coef_sel, s.delta, s.allowance2, true);
  for (std::size_t i = 0; i < m.terms.size(); ++i) {
    if (!res.effects[i].moves_estimate) continue;
    res.effects[i].moves_estimate = false;
    res.effects[i].estimate_note =
        "the other search reading (correlated noise) fits about as well on this plan: the "
        "estimate averages both readings equally, their spread added to its uncertainty";
  }
  res.ambiguous.push_back(std::move(a));
}

// The estimate after the assessment: the selected model's moved by delta, its standard errors
// widened by allowance2.
void apply_assessment(const Assessment& s, DiagnosisResult& res) {
  res.estimate_after = res.estimate_selected;
  if (s.delta.isZero(0.0) && s.allowance2 == 0.0) return;
  const double a = s.coef_sel(0) + s.delta(0), c = s.coef_sel(1) + s.delta(1);
  UnbalanceEstimate& out = res.estimate_after;
  out.amplitude = std::hypot(a, c);
  out.phase = wrap_two_pi(std::atan2(c, a));
  out.offset = s.coef_sel(2) + s.delta(2);
  out.se_amplitude = std::sqrt(out.se_amplitude * out.se_amplitude + s.allowance2);
  out.se_phase = out.amplitude > 0.0
                     ? std::sqrt(out.se_phase * out.se_phase + s.allowance2 / (out.amplitude * out.amplitude))
                     : std::numeric_limits<double>::infinity();
  out.se_offset = std::sqrt(out.se_offset * out.se_offset + s.allowance2);
}

}  // namespace

void assess(const Model& m, const AssessmentInputs& in, DiagnosisResult& res) {
  Assessment s(m, in);
  for (std::size_t i = 0; i < m.terms.size(); ++i) assess_term(s, i, res);
  if (s.guarded_any) drop_guarded_terms_together(s);
  if (in.monotone_plan && !m.ar) weigh_harmonics_against_correlated_noise(s, res);
  if (in.monotone_plan && in.other_search != nullptr) weigh_the_other_search(s, res);
  apply_assessment(s, res);
}

}  // namespace poise::estimators::detail
