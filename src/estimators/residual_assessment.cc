#include "estimators/residual_assessment.h"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <boost/math/distributions/fisher_f.hpp>
#include <cmath>
#include <cstdio>
#include <numbers>
#include "core/angles.h"

namespace poise::estimators::detail {
namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

using angles::kPi;

using angles::wrap_two_pi;

std::string fmt(const char* f, double a, double b = 0.0) {
  char buf[240];
  std::snprintf(buf, sizeof buf, f, a, b);
  return buf;
}

// (a, c, K) of the model.
UnbalanceEstimate estimate_of_model(const Model& m, const ModelData& d);

Eigen::Vector3d coefficients(const Model& m, const ModelData& d) {
  const UnbalanceEstimate e = estimate_of_model(m, d);
  return {e.amplitude * std::cos(e.phase), e.amplitude * std::sin(e.phase), e.offset};
}

UnbalanceEstimate estimate_of_model(const Model& m, const ModelData& d) { return estimate_of(m, d); }

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

}  // namespace

// Drop-one F test p of term i in model m (OLS or GLS at m's rho).
double drop_one_p(const Model& m, const ModelData& d, std::size_t i) {
  const Term& t = m.terms[i];
  if (t.cols.cols() == 0) return t.p;
  const Model r = without_term(m, i);
  const LinearFit f1 = fit_linear(m.x, d, m.ar, m.rho.rho), f0 = fit_linear(r.x, d, m.ar, m.rho.rho);
  if (!f1.ok || !f0.ok || f1.dof < 1 || !(f1.rss > 0.0)) return 0.0;
  const double q = static_cast<double>(t.cols.cols());
  const double fs = std::max(0.0, (f0.rss - f1.rss) / q) / (f1.rss / static_cast<double>(f1.dof));
  return boost::math::cdf(boost::math::complement(boost::math::fisher_f(q, static_cast<double>(f1.dof)), fs));
}

std::string term_label(const Term& t) {
  if (t.name == "outlier") return "outlier at row " + std::to_string(t.index);
  if (t.name == "step") return "step before row " + std::to_string(t.index);
  if (t.name == "exponential_drift") return fmt("exponential_drift (tau %.3g)", t.param);
  return t.label;
}

bool is_time_like(const std::string& n) {
  return n == "time_drift" || n == "time_drift_quadratic" || n == "exponential_drift" || n == "step" ||
         n == "kt_drift" || n == "autocorrelation";
}

double model_bic(const Model& m, const ModelData& d) {
  const LinearFit f = fit_linear(m.x, d, m.ar, m.rho.rho);
  if (!f.ok) return std::numeric_limits<double>::infinity();
  const double n = static_cast<double>(d.n);
  const double loglik = -0.5 * n * std::log(std::max(f.rss, d.rss_floor) / n) +
                        (m.ar ? 0.5 * std::log(1.0 - m.rho.rho * m.rho.rho) : 0.0);
  double k = static_cast<double>(m.x.cols() + (m.ar ? 1 : 0));
  for (const Term& t : m.terms) k += t.scanned > 0 ? 1.0 : 0.0;  // tau or change point
  return -2.0 * loglik + k * std::log(n);
}

Model without_term(const Model& m, std::size_t i) {
  Model out = m;
  const Term& t = m.terms[i];
  if (t.name == "autocorrelation") {
    out.ar = false;
    out.rho = RhoFit{};
  } else {
    const Index q = t.cols.cols(), first = t.first, p = m.x.cols();
    MatrixXd x(m.x.rows(), p - q);
    x << m.x.leftCols(first), m.x.rightCols(p - first - q);
    out.x = x;
    for (Term& o : out.terms) {
      if (o.name != "autocorrelation" && o.first > first) o.first -= q;
    }
  }
  out.terms.erase(out.terms.begin() + static_cast<std::ptrdiff_t>(i));
  return out;
}

UnbalanceEstimate estimate_of(const Model& m, const ModelData& d) {
  const LinearFit f = fit_linear(m.x, d, m.ar, m.rho.rho);
  UnbalanceEstimate e;
  if (!f.ok) return e;
  // (a, c, K) and their covariance; with a K_T drift referred to the first measurement,
  // where K_T is the calibrated (cold) one: (a, c, K) (1 + kappa t_start), delta method.
  Eigen::Vector3d v = f.beta.head<3>();
  Eigen::Matrix3d cov = f.cov.block<3, 3>(0, 0);
  const auto kt = std::find_if(m.terms.begin(), m.terms.end(), [](const Term& t) { return t.name == "kt_drift"; });
  if (kt != m.terms.end()) {
    const Index j = kt->first;
    const double s = 1.0 + f.beta(j) * d.t_start;
    Eigen::Matrix<double, 3, 4> jac = Eigen::Matrix<double, 3, 4>::Zero();
    jac.leftCols<3>() = s * Eigen::Matrix3d::Identity();
    jac.col(3) = v * d.t_start;
    Eigen::Matrix4d c4;
    const std::array<Index, 4> idx{0, 1, 2, j};
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) c4(r, c) = f.cov(idx[r], idx[c]);
    }
    cov = jac * c4 * jac.transpose();
    v *= s;
  }
  const double a = v(0), c = v(1);
  e.amplitude = std::hypot(a, c);
  e.phase = wrap_two_pi(std::atan2(c, a));
  e.offset = v(2);
  const Eigen::Matrix2d cov2 = cov.block<2, 2>(0, 0);
  if (e.amplitude > 0.0) {
    const Eigen::Vector2d ua(a / e.amplitude, c / e.amplitude), up(-ua(1), ua(0));
    e.se_amplitude = std::sqrt(std::max(0.0, ua.dot(cov2 * ua)));
    e.se_phase = std::sqrt(std::max(0.0, up.dot(cov2 * up))) / e.amplitude;
  } else {
    e.se_amplitude = std::sqrt(0.5 * (cov2(0, 0) + cov2(1, 1)));
    e.se_phase = std::numeric_limits<double>::infinity();
  }
  e.se_offset = std::sqrt(std::max(0.0, cov(2, 2)));
  return e;
}

Model with_term(const Model& m, const ModelData& d, Term t) {
  Model out = m;
  if (t.name == "autocorrelation") {
    out.ar = true;
  } else {
    t.first = out.x.cols();
    out.x = with_columns(out.x, t.cols);
  }
  out.terms.push_back(std::move(t));
  if (out.ar) out.rho = fit_rho(out.x, d);
  return out;
}

void assess(const Model& m, const AssessmentInputs& in, DiagnosisResult& res) {
  const ModelData& d = in.d;
  const double bic_sel = model_bic(m, d);
  const Eigen::Vector3d coef_sel = coefficients(m, d);
  const LinearFit f_sel = fit_linear(m.x, d, m.ar, m.rho.rho);
  const Eigen::Matrix2d cov_sel = f_sel.cov.block<2, 2>(0, 0);
  Eigen::Vector3d delta = Eigen::Vector3d::Zero();
  double allowance2 = 0.0;  // squared half-spread of the readings, table unit^2
  const MatrixXd one = MatrixXd::Ones(d.n, 1);
  bool guarded_any = false;
  for (std::size_t i = 0; i < m.terms.size(); ++i) {
    const Term& t = m.terms[i];
    Effect& e = res.effects[i];
    const Model rest = without_term(m, i);
    const Eigen::Vector3d coef_rest = coefficients(rest, d);
    const Eigen::Vector2d mv = coef_sel.head<2>() - coef_rest.head<2>();
    const double len = mv.norm();
    if (len > 0.0 && std::isfinite(len)) {
      const Eigen::Vector2d u = mv / len;
      const double se = std::sqrt(std::max(0.0, u.dot(cov_sel * u)));
      e.shift_se = se > 0.0 ? len / se : std::numeric_limits<double>::infinity();
    }
    if (t.name == "autocorrelation") continue;  // changes weights, not columns
    // Trade-off with the first harmonic given the rest of the model (constant kept).
    MatrixXd others(d.n, rest.x.cols() - 2);
    others << rest.x.col(2), rest.x.rightCols(rest.x.cols() - 3);
    e.r_first_harmonic = canonical_correlation(residualize(t.cols, others), residualize(m.x.leftCols(2), others));
    if (in.guarded != nullptr && std::isfinite((*in.guarded)[i])) {
      e.moves_estimate = false;  // the guard keeps the plain estimate (residual_guard.h)
      guarded_any = true;
      allowance2 += (*in.guarded)[i];
      continue;
    }
    // Readings: every candidate of the pool on the rest of the model that the design or the
    // data cannot tell from this effect.
    AmbiguousFinding a;
    a.readings.push_back({term_label(t), 0.0, estimate_of(m, d)});
    const MatrixXd te = residualize(t.cols, rest.x);
    std::string other_name;
    bool shape_readings = false;  // a time shape the data do not reject very strongly
    for (const Term& c : in.pool(rest)) {
      if (c.name == t.name && c.order == t.order) continue;
      if (!c.examined && c.cols.cols() == 0) continue;
      const double r = canonical_correlation(te, residualize(c.cols, rest.x));
      if (r < kWeakCorrelation) continue;
      const Model alt = with_term(rest, d, c);
      const double db = model_bic(alt, d) - bic_sel;
      // Occam's window for a time shape that trades off with the unbalance (r >= 0.5 with
      // the first harmonic): which shape holds decides the estimate, so every other time
      // shape the data do not reject very strongly (BIC within 10, Kass and Raftery 1995) is
      // a reading, and the readings count equally: a K_T drift read as a step or as a linear
      // drift moved the estimate 4-7 SE the wrong way in 7 of 100 independent tables.
      const bool shape_window =
          is_time_like(t.name) && is_time_like(c.name) && e.r_first_harmonic >= kWeakCorrelation && db < kBicVeryStrong;
      shape_readings = shape_readings || (shape_window && db >= kBicIndistinct);
      if ((r >= kConfounded && db < kBicStrong) || db < kBicIndistinct || shape_window) {
        a.readings.push_back({term_label(c), db, estimate_of(alt, d)});
        if (r > a.correlation) a.correlation = r, other_name = c.name;
      }
    }
    // A time-shaped effect that trades off with the unbalance against correlated noise in
    // its place: a wander of AR(1) noise holds steps and drifts, and the BIC weights decide.
    if (!m.ar && is_time_like(t.name) && e.r_first_harmonic >= kWeakCorrelation) {
      const Model alt = with_term(rest, d, Term("autocorrelation", "autocorrelation"));
      const double db = model_bic(alt, d) - bic_sel;
      if (db < kBicStrong) {
        a.readings.push_back({"autocorrelation (AR(1) errors) instead of " + term_label(t), db, estimate_of(alt, d)});
        if (other_name.empty()) other_name = "autocorrelation";
      }
    }
    const bool harmonic_confounded = e.r_first_harmonic >= kFirstHarmonicLimit && drop_one_p(m, d, i) >= kIdentifiedP;
    if (harmonic_confounded) {
      a.readings.push_back(
          {"no effect (part of the first harmonic)", model_bic(rest, d) - bic_sel, estimate_of(rest, d)});
      a.correlation = std::max(a.correlation, e.r_first_harmonic);
      if (other_name.empty()) other_name = "first harmonic";
    }
    const bool correlated_outlier = t.name == "outlier" && (in.residual_correlated || m.ar);
    if (a.readings.size() > 1) {
      e.moves_estimate = false;
      a.why = term_label(t) + " and " + a.readings[1].effects +
              (a.correlation > 0.0 ? fmt(" are collinear under this plan (canonical correlation %.3f)", a.correlation)
                                   : std::string(" are not told apart by these data (BIC within 6)")) +
              (in.monotone_plan ? "; time order follows angle order" : "");
      a.plan = separating_plan(t.name == "harmonic" ? "harmonic" : t.name,
                               other_name == "harmonic" ? "harmonic" : other_name);
      if (harmonic_confounded) {
        // Not identified against the first harmonic: the estimate does not take it; the
        // spread of the readings goes into its uncertainty.
        double spread = 0.0;
        for (const Reading& r : a.readings) {
          const Eigen::Vector2d x(r.estimate.amplitude * std::cos(r.estimate.phase),
                                  r.estimate.amplitude * std::sin(r.estimate.phase));
          spread = std::max(spread, (x - coef_rest.head<2>()).norm());
        }
        delta += coef_rest - coef_sel;
        allowance2 += 0.25 * spread * spread;
        e.estimate_note =
            "trades off with the first harmonic and is not identified (drop-one p >= "
            "1e-4): the estimate does not take it; the readings' spread is added to "
            "its uncertainty";
      } else {
        average_readings(a, coef_sel, delta, allowance2, shape_readings);
        e.estimate_note = shape_readings
                              ? "the time shape trades off with the unbalance and the data do not single it out "
                                "(another shape within 10 BIC): the estimate averages the readings equally, their "
                                "spread added to its uncertainty"
                              : "ambiguous: the estimate averages the readings with BIC weights, their spread "
                                "added to its uncertainty";
      }
      res.ambiguous.push_back(std::move(a));
    } else if (correlated_outlier) {
      e.moves_estimate = false;
      delta += coef_rest - coef_sel;
      allowance2 += 0.25 * mv.squaredNorm();
      e.estimate_note =
          "in correlated noise a single excursion is not told from the noise's own: "
          "tentative, the estimate does not take it";
    }
  }
  // The guarded effects dropped together: a term collinear with another moves the estimate
  // far when dropped alone, and such moves do not add.
  if (guarded_any) {
    Model plain = m;
    for (std::size_t i = m.terms.size(); i-- > 0;) {
      if (std::isfinite((*in.guarded)[i])) plain = without_term(plain, i);
    }
    if (plain.ar) plain.rho = fit_rho(plain.x, d);
    delta += coefficients(plain, d) - coef_sel;
  }
  // On a plan where time follows angle, the harmonics found (together) against AR(1) errors
  // in their place: a smooth function of angle is then a smooth function of time, and only a
  // repeated or reordered sweep tells a deterministic harmonic from correlated noise.
  if (in.monotone_plan && !m.ar) {
    Model alt = m;
    std::string names;
    std::vector<std::size_t> members;
    for (std::size_t i = m.terms.size(); i-- > 0;) {
      if (m.terms[i].name != "harmonic" || !res.effects[i].moves_estimate) continue;
      names = m.terms[i].label + (names.empty() ? "" : ", " + names);
      members.push_back(i);
      alt = without_term(alt, i);
    }
    if (!members.empty()) {
      alt = with_term(alt, d, Term("autocorrelation", "autocorrelation"));
      const double db = model_bic(alt, d) - bic_sel;
      {
        AmbiguousFinding a;
        a.readings.push_back({names, 0.0, estimate_of(m, d)});
        a.readings.push_back({"autocorrelation (AR(1) errors) instead of " + names, db, estimate_of(alt, d)});
        a.correlation = 1.0;
        a.why = names +
                " and correlated noise: time order follows angle order, so a smooth "
                "function of angle is one of time; whatever the BIC says, it rests on "
                "the AR(1) form of the noise, which the plan cannot check";
        a.plan = separating_plan("harmonic", "autocorrelation");
        average_readings(a, coef_sel, delta, allowance2);
        for (std::size_t i : members) {
          res.effects[i].moves_estimate = false;
          res.effects[i].estimate_note =
              "ambiguous with correlated noise on this plan: the estimate averages the two "
              "readings with BIC weights, their spread added to its uncertainty";
        }
        res.ambiguous.push_back(std::move(a));
      }
    }
  }
  // The two searches (AR(1) allowed first, AR(1) deferred) ended in different models on a plan
  // where time follows angle: correlated noise against time-shaped effects rests on the AR(1)
  // form of the noise, which this plan cannot check; both readings count equally.
  if (in.monotone_plan && in.other_search != nullptr) {
    const Model& o = *in.other_search;
    bool open = false;  // an effect of the selected model not in the other one still moves
    for (std::size_t i = 0; i < m.terms.size(); ++i) {
      const bool shared = std::any_of(o.terms.begin(), o.terms.end(), [&](const Term& x) {
        return x.name == m.terms[i].name && x.order == m.terms[i].order;
      });
      if (!shared && res.effects[i].moves_estimate) open = true;
    }
    if (open) {
      AmbiguousFinding a;
      a.readings.push_back({in.selected_summary, 0.0, estimate_of(m, d)});
      a.readings.push_back({in.other_summary, model_bic(o, d) - bic_sel, estimate_of(o, d)});
      a.correlation = 1.0;
      a.why = in.selected_summary + " and " + in.other_summary +
              ": the search ends in either, and time order follows angle order, so which one "
              "holds rests on the AR(1) form of the noise, which the plan cannot check";
      a.plan = separating_plan("harmonic", "autocorrelation");
      average_readings(a, coef_sel, delta, allowance2, true);
      for (std::size_t i = 0; i < m.terms.size(); ++i) {
        if (!res.effects[i].moves_estimate) continue;
        res.effects[i].moves_estimate = false;
        res.effects[i].estimate_note =
            "the other search reading (correlated noise) fits about as well on this plan: the "
            "estimate averages both readings equally, their spread added to its uncertainty";
      }
      res.ambiguous.push_back(std::move(a));
    }
  }
  res.estimate_after = res.estimate_selected;
  if (delta.isZero(0.0) && allowance2 == 0.0) return;
  const double a = coef_sel(0) + delta(0), c = coef_sel(1) + delta(1);
  UnbalanceEstimate& out = res.estimate_after;
  out.amplitude = std::hypot(a, c);
  out.phase = wrap_two_pi(std::atan2(c, a));
  out.offset = coef_sel(2) + delta(2);
  out.se_amplitude = std::sqrt(out.se_amplitude * out.se_amplitude + allowance2);
  out.se_phase = out.amplitude > 0.0
                     ? std::sqrt(out.se_phase * out.se_phase + allowance2 / (out.amplitude * out.amplitude))
                     : std::numeric_limits<double>::infinity();
  out.se_offset = std::sqrt(out.se_offset * out.se_offset + allowance2);
}

}  // namespace poise::estimators::detail
