#include "estimators/residual_candidates.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
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
    char buf[120];
    std::snprintf(buf, sizeof buf, "tau = %.4g, Bonferroni over %d time constants", best.param,
                  best.scanned);
    best.note = buf;
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

}  // namespace poise::estimators::detail
