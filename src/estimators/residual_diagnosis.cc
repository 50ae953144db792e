#include "estimators/residual_diagnosis.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>
#include <utility>

#include "core/angles.h"
#include "core/error.h"
#include "core/format.h"
#include "estimators/residual_assessment.h"
#include "estimators/residual_candidates.h"
#include "estimators/residual_diagnosis_model.h"
#include "estimators/residual_effects.h"
#include "estimators/residual_guard.h"
#include "estimators/residual_plan.h"
#include "estimators/sine_fit.h"

namespace poise::estimators {
namespace {

using detail::autocorrelation_test;
using detail::describe;
using detail::fit_linear;
using detail::fit_rho;
using detail::holm;
using detail::LinearFit;
using detail::Model;
using detail::nested_test;
using detail::outlier_family;
using detail::RhoFit;
using detail::Term;
using detail::to_effect;
using detail::with_columns;
using Data = detail::ModelData;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

using angles::kPi;
constexpr double kDegPerRad = 180.0 / kPi;
constexpr int kMaxRounds = 200;  // the search ends long before: each round adds a column set
using angles::wrap_two_pi;

std::vector<Term> round_candidates(const Model& m, const Data& d, const TorqueTable& table,
                                   const std::vector<double>& t_c, int max_harmonic, bool kt) {
  const Index n = d.n;
  std::vector<Term> c;
  for (int k = 2; k <= max_harmonic; ++k) {
    if (m.has("harmonic", k)) continue;
    Term h("harmonic", "harmonic " + std::to_string(k), k);
    h.cols.resize(n, 2);
    for (Index i = 0; i < n; ++i) {
      const double th = table.theta_rad[static_cast<std::size_t>(i)];
      h.cols(i, 0) = std::sin(k * th), h.cols(i, 1) = std::cos(k * th);
    }
    c.push_back(std::move(h));
  }
  const auto column_term = [&](const std::string& name, auto value) {
    Term t(name, name);
    t.cols.resize(n, 1);
    for (Index i = 0; i < n; ++i) t.cols(i, 0) = value(static_cast<std::size_t>(i));
    c.push_back(std::move(t));
  };
  if (!m.has("time_drift")) column_term("time_drift", [&](std::size_t i) { return t_c[i]; });
  if (m.has("time_drift") && !m.has("time_drift_quadratic")) {
    column_term("time_drift_quadratic", [&](std::size_t i) { return t_c[i] * t_c[i]; });
  }
  if (!m.has("kt_drift") && kt) c.push_back(detail::kt_drift_term(m, d, t_c));
  const bool both = !table.sweep.empty() && std::count(table.sweep.begin(), table.sweep.end(), 1) > 0 &&
                    std::count(table.sweep.begin(), table.sweep.end(), -1) > 0;
  if (!m.has("direction_offset")) {
    column_term("direction_offset", [&](std::size_t i) { return both ? static_cast<double>(table.sweep[i]) : 0.0; });
    if (!both) {
      c.back().note = table.sweep.empty() ? "not examined: the table has no sweep column"
                                          : "not examined: only one sweep direction occurs";
    }
  }
  return c;
}

void check(const TorqueTable& t, const DiagnosisOptions& o) {
  const std::size_t n = t.theta_rad.size();
  require(std::isfinite(o.alpha) && o.alpha > 0.0 && o.alpha < 1.0,
          "diagnose_residuals: alpha = " + std::to_string(o.alpha) + "; expected 0 < alpha < 1");
  require(o.max_harmonic >= 1,
          "diagnose_residuals: max_harmonic = " + std::to_string(o.max_harmonic) + "; expected >= 1 (1 = none)");
  require(
      t.torque.size() == n && (t.time_s.empty() || t.time_s.size() == n) && (t.sweep.empty() || t.sweep.size() == n),
      "diagnose_residuals: columns of different lengths (" + std::to_string(n) + " angles, " +
          std::to_string(t.torque.size()) + " torques, " + std::to_string(t.time_s.size()) + " times, " +
          std::to_string(t.sweep.size()) + " sweeps); expected one of each per point, time and sweep optional");
  for (double v : t.time_s) require(std::isfinite(v), "diagnose_residuals: a time is not finite");
}

struct SearchInputs {
  const Data& d;
  const TorqueTable& table;
  const std::vector<double>& t;  // time from its mean
  const DiagnosisOptions& options;
  int max_harmonic;
};

struct Search {
  Model m;
  int rounds = 0;
  std::vector<std::string> tested, notes;
  std::string summary;             // effects in the order added, e.g. "harmonic 2, time_drift"
  std::vector<std::string> found;  // the same, sorted: the model whatever the order
  double bic = 0.0;                // -2 ln L + k ln n of the final model (ML form, rho at its estimate)
};

// Every column candidate for a model (families: the best member), examined ones only.
detail::CandidatePool make_pool(const SearchInputs& in) {
  return [&in](const Model& m) {
    std::vector<Term> c = round_candidates(m, in.d, in.table, in.t, in.max_harmonic, in.options.kt_drift);
    std::vector<Term> out;
    for (Term& t : c) {
      if (t.note.empty() && nested_test(m, in.d, t)) out.push_back(std::move(t));
    }
    if (in.options.steps && !m.has("step")) out.push_back(detail::step_family(m, in.d));
    if (in.options.exponential && !m.has("exponential_drift")) {
      out.push_back(detail::exponential_family(m, in.d, in.t));
    }
    out.erase(std::remove_if(out.begin(), out.end(), [](const Term& t) { return !t.examined; }), out.end());
    return out;
  };
}

// Correlated noise that its own test suggests (p < alpha) but the adjustment over the round's
// candidates does not establish: said, with the plan that would tell it from a smooth effect;
// no correction is applied.
void note_suggested_autocorrelation(const SearchInputs& in, const std::vector<Term>& round,
                                    std::vector<std::string>& notes) {
  const auto ar = std::find_if(round.begin(), round.end(), [](const Term& t) { return t.name == "autocorrelation"; });
  const double alpha = in.options.alpha;
  if (ar == round.end() || !ar->examined || !(ar->p < alpha) || ar->p_adj < alpha) return;
  const auto examined = std::count_if(round.begin(), round.end(), [](const Term& t) { return t.examined; });
  const bool monotone = detail::monotone_plan(in.table, in.d.order);
  notes.push_back(fmt::format(
      "{}: p = {:.3g} on its own, {:.3g} after the adjustment over the round's {} candidates: correlated "
      "noise is suggested, not established, and no correction is applied; {}",
      ar->note.empty() ? ar->label : ar->label + " (" + ar->note + ")", ar->p, ar->p_adj, static_cast<double>(examined),
      monotone ? "on this one-direction sweep it cannot be told from a smooth effect in angle or time: the "
                 "same positions swept in the other direction (or in random order) would separate them"
               : "a repeat of the test, or the positions in random order, would establish it"));
}

// Forward stepwise search from `start` (the rounds described in residual_diagnosis.h). With
// ar_last, AR(1) is picked only in a round where no column candidate qualifies.
Search search(const SearchInputs& in, const Model& start, bool ar_last) {
  const Data& d = in.d;
  const double alpha = in.options.alpha;
  Search s;
  s.m = start;
  Model& m = s.m;
  while (s.rounds < kMaxRounds) {
    ++s.rounds;
    std::vector<Term> c = round_candidates(m, d, in.table, in.t, in.max_harmonic, in.options.kt_drift);
    for (Term& term : c) {
      if (term.note.empty()) nested_test(m, d, term);
    }
    if (in.options.steps && !m.has("step")) c.push_back(detail::step_family(m, d));
    if (in.options.exponential && !m.has("exponential_drift")) {
      c.push_back(detail::exponential_family(m, d, in.t));
    }
    if (in.options.outliers) c.push_back(outlier_family(m, d));
    if (in.options.autocorrelation && !m.ar) c.push_back(autocorrelation_test(m, d));
    holm(c);
    const Term* pick = nullptr;
    for (int pass = ar_last ? 0 : 1; pass < 2 && !pick; ++pass) {
      for (const Term& term : c) {
        if ((pass == 0 && term.name == "autocorrelation") || !term.examined || !(term.p_adj < alpha) ||
            !(term.delta_bic < 0.0)) {
          continue;
        }
        if (!pick || term.p_adj < pick->p_adj || (term.p_adj == pick->p_adj && term.p < pick->p)) {
          pick = &term;
        }
      }
    }
    if (!pick) {
      for (const Term& term : c) s.tested.push_back(describe(term));
      note_suggested_autocorrelation(in, c, s.notes);
      break;
    }
    Term added = *pick;
    added.first = m.x.cols();
    added.round = s.rounds;
    if (added.name == "autocorrelation") {
      m.ar = true;
    } else {
      m.x = with_columns(m.x, added.cols);
    }
    m.terms.push_back(std::move(added));
    if (!m.ar) continue;
    // AR(1) stays only while the columns leave the residuals autocorrelated: a missing smooth
    // effect looks like correlated errors until it is in the model.
    const Term check = autocorrelation_test(m, d);
    if (check.examined && check.p < alpha && check.delta_bic < 0.0) {
      m.rho = fit_rho(m.x, d);
      continue;
    }
    const auto ar =
        std::find_if(m.terms.begin(), m.terms.end(), [](const Term& x) { return x.name == "autocorrelation"; });
    s.notes.emplace_back(
        fmt::format("autocorrelation, added in round {}, was removed in round {}: with {} in the "
                    "model it has p = {:.3g}, delta_BIC = {:+.2f}",
                    ar->round, s.rounds, m.terms.back().label, check.p, check.delta_bic));
    m.terms.erase(ar);
    m.ar = false;
    m.rho = RhoFit{};
  }
  detail::drop_redundant(d, m, s.notes);
  detail::compare_time_shapes(d, make_pool(in), m, s.notes);
  for (const Term& term : m.terms) {
    s.found.push_back(term.name == "outlier" ? "outlier at row " + std::to_string(term.index) : term.label);
    s.summary += (s.summary.empty() ? "" : ", ") + s.found.back();
  }
  std::sort(s.found.begin(), s.found.end());
  if (s.summary.empty()) s.summary = "no effect";
  s.bic = detail::model_bic(m, d);
  return s;
}

}  // namespace

namespace {

// The table as the fits use it: the torque, its time order, and the times about their mean
// (the row index when the table has no times).
Data data_of_table(const TorqueTable& table, std::vector<double>& t) {
  const std::size_t n = table.size();
  Data d;
  d.n = static_cast<Index>(n);
  d.y = Eigen::Map<const VectorXd>(table.torque.data(), d.n);
  d.rss_floor = 1e-28 * std::max(d.y.squaredNorm(), 1e-300);
  t.resize(n);
  if (table.time_s.empty()) {
    std::iota(t.begin(), t.end(), 0.0);
  } else {
    t = table.time_s;
  }
  d.order.resize(n);
  std::iota(d.order.begin(), d.order.end(), std::size_t{0});
  std::stable_sort(d.order.begin(), d.order.end(), [&](auto a, auto b) { return t[a] < t[b]; });
  const double t_mean = std::accumulate(t.begin(), t.end(), 0.0) / static_cast<double>(n);
  for (double& v : t) v -= t_mean;
  d.t_start = t[d.order[0]];
  return d;
}

// The search's model, and where the two searches (AR(1) allowed in any round, AR(1) deferred)
// ended in different models, the other one.
struct ModelSelection {
  Search selected;
  bool other = false;
  Model other_model;
  std::string other_summary;
};

ModelSelection select_model(const SearchInputs& in, const Model& start) {
  ModelSelection out;
  out.selected = search(in, start, false);
  if (!in.options.autocorrelation) return out;
  Search& s = out.selected;
  Search a = search(in, start, true);
  if (a.found == s.found) return out;
  const bool keep_a = a.bic < s.bic;
  out.other = true;
  out.other_model = keep_a ? s.m : a.m;
  out.other_summary = keep_a ? s.summary : a.summary;
  std::string note = fmt::format(
      "The search with AR(1) allowed in any round found {} (BIC {:.2f}); with AR(1) "
      "deferred until no column effect qualifies it found {} (BIC {:.2f}). The "
      "lower BIC is kept: {}.",
      s.summary, s.bic, a.summary, a.bic, keep_a ? "the second" : "the first");
  if (keep_a) s = std::move(a);
  s.notes.push_back(std::move(note));
  return out;
}

// The first harmonic alone (before) and the selected model (after): effects, RMSE, estimates,
// fitted values and residuals per row.
void fill_fits(const TorqueTable& table, const Data& d, const Model& m, DiagnosisResult& res) {
  const std::size_t n = table.size();
  const SineFitResult base = fit_sine(table.theta_rad, table.torque);
  const LinearFit f = fit_linear(m.x, d, m.ar, m.rho.rho);
  for (const Term& term : m.terms) res.effects.push_back(to_effect(term, m, f, table));
  res.rmse_before = base.rmse;
  res.rmse_after = std::sqrt(f.rss / static_cast<double>(n));
  res.estimate_before = {base.amplitude, base.phase, base.offset, base.se_amplitude, base.se_phase, base.se_offset};
  res.estimate_selected = detail::estimate_of(m, d);
  for (std::size_t i = 0; i < n; ++i) {
    const auto k = static_cast<Index>(i);
    res.fitted_before.push_back(sine_fit_predict(base, table.theta_rad[i]));
    res.residual_before.push_back(base.residuals[i]);
    res.residual_after.push_back(f.resid(k));
    res.fitted_after.push_back(table.torque[i] - f.resid(k));
  }
}

// The omnibus check of the final residual; true when its whiteness tests (Ljung-Box, runs)
// reject at alpha.
bool check_final_residual(const TorqueTable& table, const Data& d, const Model& m, const DiagnosisOptions& options,
                          DiagnosisResult& res) {
  const std::size_t n = table.size();
  OmnibusInput oi;
  oi.residual = res.residual_after;
  oi.order = d.order;
  oi.theta_deg = table.theta_deg.empty() ? std::vector<double>(n) : table.theta_deg;
  if (table.theta_deg.empty()) {
    for (std::size_t i = 0; i < n; ++i) oi.theta_deg[i] = table.theta_rad[i] * kDegPerRad;
  }
  oi.time_s = table.time_s;
  oi.lines = table.rows.size() == n ? table.rows : std::vector<std::size_t>{};
  oi.parameters = static_cast<std::size_t>(m.x.cols());
  oi.ar = m.ar;
  oi.noise = options.noise;
  oi.design = m.x;
  if (table.torque_se.size() == n) oi.noise_per_point = table.torque_se;
  oi.alpha = options.alpha;
  res.omnibus = omnibus_check(oi);
  bool correlated = false;
  for (const StructureTest& st : res.omnibus.tests) {
    if ((st.name == "ljung_box" || st.name == "runs") && st.examined && st.p_value < options.alpha) {
      correlated = true;
    }
  }
  return correlated;
}

void add_not_identifiable_scales(DiagnosisResult& res) {
  res.not_identifiable.emplace_back(
      "turntable_angle_scale",
      "a scale error of the turntable angle (or an error of its zero) changes the first harmonic "
      "itself: the unbalance phase and amplitude carry it and no residual of one test shows it; "
      "it needs a calibration of the turntable against an angle standard (polygon and "
      "autocollimator, or an encoder of known accuracy)");
  res.not_identifiable.emplace_back("kt_scale",
                                    "a constant error of K_T scales the whole torque: it needs a calibration with a "
                                    "known load (--load-torque), not a residual");
}

}  // namespace

DiagnosisResult diagnose_residuals(const TorqueTable& table, const DiagnosisOptions& options) {
  check(table, options);
  const std::size_t n = table.size();
  std::vector<double> t;
  const Data d = data_of_table(table, t);

  DiagnosisResult res;
  res.max_harmonic = std::max(1, std::min(options.max_harmonic, (static_cast<int>(n) - 6) / 2));
  Model start;
  start.x.resize(d.n, 3);
  for (Index i = 0; i < d.n; ++i) {
    const double th = table.theta_rad[static_cast<std::size_t>(i)];
    start.x(i, 0) = std::sin(th), start.x(i, 1) = std::cos(th), start.x(i, 2) = 1.0;
  }
  const SearchInputs in{d, table, t, options, res.max_harmonic};
  ModelSelection sel = select_model(in, start);
  const Model& m = sel.selected.m;
  res.rounds = sel.selected.rounds;
  res.tested = std::move(sel.selected.tested);
  res.notes = std::move(sel.selected.notes);
  fill_fits(table, d, m, res);

  // The plan as the data show it.
  const bool monotone = detail::monotone_plan(table, d.order);
  res.plan = detail::describe_plan(table, d.order, monotone);
  const detail::CandidatePool pool = make_pool(in);
  res.collinearity = detail::plan_collinearity(start, d, pool);

  // Omnibus check of the final residual, then what the estimate takes: the guard, the
  // assessment of each effect, the families.
  detail::AssessmentInputs ai(d, pool);
  ai.monotone_plan = monotone;
  ai.residual_correlated = check_final_residual(table, d, m, options, res);
  if (sel.other) {
    ai.other_search = &sel.other_model;
    ai.selected_summary = sel.selected.summary;
    ai.other_summary = sel.other_summary;
  }
  detail::GuardInputs gi(d, pool);
  gi.alpha = options.alpha;
  gi.monotone_plan = monotone;
  const detail::GuardResult guard = detail::guard_estimate(m, gi, res);
  ai.guarded = &guard.allowance;
  detail::assess(m, ai, res);
  detail::name_families(m, d, pool, guard, res);
  add_not_identifiable_scales(res);
  return res;
}

KnownLoadErrors known_load_errors(const DiagnosisResult& r, double true_amplitude, double true_phase_rad) {
  const auto error = [&](const UnbalanceEstimate& e) {
    double dphi = std::remainder(e.phase - true_phase_rad, 2.0 * kPi);
    if (dphi <= -kPi) dphi += 2.0 * kPi;
    const double dx = e.amplitude * std::cos(e.phase) - true_amplitude * std::cos(true_phase_rad);
    const double dy = e.amplitude * std::sin(e.phase) - true_amplitude * std::sin(true_phase_rad);
    return EstimateError{e.amplitude - true_amplitude, dphi * kDegPerRad, std::hypot(dx, dy)};
  };
  return {error(r.estimate_before), error(r.estimate_after)};
}

}  // namespace poise::estimators
