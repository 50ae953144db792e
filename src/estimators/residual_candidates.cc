#include "estimators/residual_candidates.h"

#include "core/format.h"
#include "estimators/residual_assessment.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace poise::estimators::detail {
namespace {

using Eigen::Index;
using Eigen::MatrixXd;

constexpr int kTaus = 12;
constexpr std::size_t kMinSegment = 3;  // points either side of a step

}  // namespace

MatrixXd step_column(const ModelData& d, std::size_t k) {
  MatrixXd c = MatrixXd::Zero(d.n, 1);
  for (std::size_t j = k; j < d.order.size(); ++j) c(static_cast<Index>(d.order[j]), 0) = 1.0;
  return c;
}

MatrixXd exponential_column(const std::vector<double>& t, double tau) {
  const double t0 = *std::min_element(t.begin(), t.end());
  MatrixXd c(static_cast<Index>(t.size()), 1);
  for (std::size_t i = 0; i < t.size(); ++i) c(static_cast<Index>(i), 0) = std::exp(-(t[i] - t0) / tau);
  return c;
}

std::vector<double> exponential_taus(const std::vector<double>& t) {
  const auto [lo, hi] = std::minmax_element(t.begin(), t.end());
  const double span = *hi - *lo;
  std::vector<double> taus;
  if (!(span > 0.0)) return taus;
  for (int k = 0; k < kTaus; ++k) {
    taus.push_back(span / 30.0 * std::pow(30.0, static_cast<double>(k) / (kTaus - 1)));
  }
  return taus;
}

namespace {

Term scan(const Model& m, const ModelData& d, std::vector<Term> members, const std::string& name,
          const std::string& what) {
  Term best(name, name);
  double best_p = 2.0;
  int tested = 0;
  for (Term& t : members) {
    if (!nested_test(m, d, t, false)) continue;  // at the model's rho: the scan
    ++tested;
    if (t.p < best_p) best_p = t.p, best = t;
  }
  if (tested == 0) {
    best.note = "not examined: no " + what + " can be tested";
    return best;
  }
  if (m.ar) nested_test(m, d, best);  // the member picked, at the rho of the larger model
  best.scanned = tested;
  best.p = std::min(1.0, tested * best.p);
  return best;
}

}  // namespace

Term step_family(const Model& m, const ModelData& d) {
  std::vector<Term> members;
  const std::size_t n = d.order.size();
  for (std::size_t k = kMinSegment; k + kMinSegment <= n; ++k) {
    Term t("step", "step", 0, static_cast<int>(d.order[k]));
    t.cols = step_column(d, k);
    t.param = static_cast<double>(k);
    members.push_back(std::move(t));
  }
  Term best = scan(m, d, std::move(members), "step", "change point");
  if (best.examined) {
    best.note = "largest before row " + std::to_string(best.index) + ", Bonferroni over " +
                std::to_string(best.scanned) + " change points";
  }
  return best;
}

Term exponential_family(const Model& m, const ModelData& d, const std::vector<double>& t) {
  std::vector<Term> members;
  for (double tau : exponential_taus(t)) {
    Term e("exponential_drift", "exponential_drift");
    e.cols = exponential_column(t, tau);
    e.param = tau;
    members.push_back(std::move(e));
  }
  Term best = scan(m, d, std::move(members), "exponential_drift", "time constant");
  if (best.examined) {
    best.note = fmt::format("tau = {:.4g}, Bonferroni over {} time constants", best.param, best.scanned);
  }
  return best;
}

Term kt_drift_term(const Model& m, const ModelData& d, const std::vector<double>& t) {
  Term k("kt_drift", "kt_drift");
  const LinearFit f = fit_linear(m.x, d, m.ar, m.rho.rho);
  if (!f.ok) {
    k.note = "not examined: the current model does not fit";
    return k;
  }
  k.cols.resize(d.n, 1);
  for (Index i = 0; i < d.n; ++i) {
    const double mi = f.beta(0) * m.x(i, 0) + f.beta(1) * m.x(i, 1) + f.beta(2) * m.x(i, 2);
    k.cols(i, 0) = t[static_cast<std::size_t>(i)] * mi;
  }
  return k;
}

static bool is_time_shape(const std::string& n) {
  return n == "time_drift" || n == "time_drift_quadratic" || n == "exponential_drift" || n == "step" || n == "kt_drift";
}

// The time-shaped effects the search added (linear and quadratic drift, step, settling, K_T
// drift) are compared, as a group, with each single time shape on the rest of the model;
// the lowest BIC (scanned tau or change point counted as a parameter) is kept. A saturating
// drift then is not left as linear plus quadratic, nor a K_T drift as an additive one.
void compare_time_shapes(const ModelData& d, const CandidatePool& pool, Model& m, std::vector<std::string>& notes) {
  std::vector<std::size_t> group;
  for (std::size_t i = 0; i < m.terms.size(); ++i) {
    if (is_time_shape(m.terms[i].name)) group.push_back(i);
  }
  if (group.empty()) return;
  Model rest = m;
  for (auto it = group.rbegin(); it != group.rend(); ++it) rest = without_term(rest, *it);
  const double bic_now = model_bic(m, d);
  double best_bic = bic_now;
  Model best;
  std::string best_label;
  for (Term& c : pool(rest)) {
    if (!is_time_shape(c.name) || c.name == "time_drift_quadratic") continue;
    Model alt = rest;
    c.first = alt.x.cols();
    c.round = m.terms[group.back()].round;
    c.p_adj = c.p;
    alt.x = with_columns(alt.x, c.cols);
    alt.terms.push_back(c);
    if (alt.ar) alt.rho = fit_rho(alt.x, d);
    const double b = model_bic(alt, d);
    if (b < best_bic - 1e-9) best_bic = b, best = alt, best_label = c.label;
  }
  if (best_label.empty()) return;
  std::string was;
  for (std::size_t i : group) was += (was.empty() ? "" : " + ") + m.terms[i].label;
  notes.emplace_back(
      fmt::format("the time-shaped effects {} were replaced by {} alone: lower BIC ({:.2f} against "
                  "{:.2f}, a scanned time constant or change point counted as a parameter)",
                  was, best_label, best_bic, bic_now));
  m = std::move(best);
}

// Backward elimination after the forward search: an effect whose removal lowers the BIC of
// the final model (AR(1) refitted) is dropped, with a note. A step or an outlier picked early
// in correlated noise is then not kept once AR(1) explains the noise.
void drop_redundant(const ModelData& d, Model& m, std::vector<std::string>& notes) {
  for (;;) {
    const double now = model_bic(m, d);
    double best = now;
    std::size_t pick = m.terms.size();
    Model best_model;
    for (std::size_t i = 0; i < m.terms.size(); ++i) {
      if (m.terms[i].name == "autocorrelation") continue;
      Model alt = without_term(m, i);
      if (alt.ar) alt.rho = fit_rho(alt.x, d);
      const double b = model_bic(alt, d);
      if (b < best - 1e-9) best = b, pick = i, best_model = std::move(alt);
    }
    if (pick == m.terms.size()) return;
    notes.emplace_back(
        fmt::format("{}, added in round {}, was dropped from the final model: without it the BIC is "
                    "lower ({:.2f} against {:.2f})",
                    m.terms[pick].label, m.terms[pick].round, best, now));
    m = std::move(best_model);
  }
}

}  // namespace poise::estimators::detail
