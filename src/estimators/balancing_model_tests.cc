#include "estimators/balancing_model_tests.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

#include <fmt/format.h>
#include <Eigen/Dense>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/fisher_f.hpp>

#include "core/format.h"
#include "estimators/complex_fit.h"

namespace poise::estimators {
namespace {

using complex_fit::CMatrix;
using complex_fit::CVector;
using complex_fit::extra_sum_of_squares_p;
using complex_fit::Fit;
using complex_fit::fit;
using complex_fit::rms;

// The campaign's calibration rows (runs with known masses, check runs out) and check rows.
struct Rows {
  CMatrix w, y;  // masses (n x P), readings (n x S)
  CMatrix check_w, check_y;
};

Rows rows_of(const std::vector<BalancingRun>& runs, std::size_t planes) {
  std::vector<const BalancingRun*> cal, chk;
  for (const auto& r : runs) {
    if (r.masses) (r.check ? chk : cal).push_back(&r);
  }
  const auto sensors = static_cast<Eigen::Index>(cal.empty() ? 0 : cal.front()->readings.size());
  const auto p = static_cast<Eigen::Index>(planes);
  Rows out;
  auto fill = [&](const std::vector<const BalancingRun*>& list, CMatrix& w, CMatrix& y) {
    w.resize(static_cast<Eigen::Index>(list.size()), p);
    y.resize(static_cast<Eigen::Index>(list.size()), sensors);
    for (std::size_t i = 0; i < list.size(); ++i) {
      const auto row = static_cast<Eigen::Index>(i);
      for (Eigen::Index j = 0; j < p; ++j) w(row, j) = (*list[i]->masses)[static_cast<std::size_t>(j)];
      for (Eigen::Index s = 0; s < sensors; ++s) y(row, s) = list[i]->readings[static_cast<std::size_t>(s)];
    }
  };
  fill(cal, out.w, out.y);
  fill(chk, out.check_w, out.check_y);
  return out;
}

CMatrix base_design(const CMatrix& w) {
  CMatrix x(w.rows(), w.cols() + 1);
  x.col(0).setOnes();
  x.rightCols(w.cols()) = w;
  return x;
}

// The extra-sum-of-squares test of `augmented` over the base design, sensor by sensor, the
// p-values combined by Fisher's method. Returns nothing where the extra terms add no rank or
// leave no degrees of freedom.
struct Combined {
  double p_value = 1.0;
  double rss_before = 0.0, rss_after = 0.0;
  std::vector<Fit> after;  // per sensor
};
std::optional<Combined> extra_terms_test(const CMatrix& y, const CMatrix& base,
                                         const std::function<CMatrix(Eigen::Index sensor)>& augmented) {
  Combined c;
  double fisher = 0.0;
  const Eigen::Index n = y.rows();
  for (Eigen::Index s = 0; s < y.cols(); ++s) {
    const Fit f0 = fit(base, y.col(s));
    const Fit f1 = fit(augmented(s), y.col(s));
    const Eigen::Index q = f1.rank - f0.rank, nu = n - f1.rank;
    if (q <= 0 || nu <= 0 || !(f1.rss > 0.0)) return std::nullopt;
    const double p = extra_sum_of_squares_p(f0, f1, q, nu);
    fisher += -2.0 * std::log(std::max(p, 1e-300));
    c.rss_before += f0.rss;
    c.rss_after += f1.rss;
    c.after.push_back(f1);
  }
  c.p_value =
      boost::math::cdf(boost::math::complement(boost::math::chi_squared(2.0 * static_cast<double>(y.cols())), fisher));
  return c;
}

ModelTest lack_of_fit(const Rows& r) {
  ModelTest t;
  t.name = "lack of fit";
  // Repeats: rows with the same masses (the same run read again, or two runs of equal masses).
  std::vector<Eigen::Index> group_of(static_cast<std::size_t>(r.w.rows()));
  std::vector<Eigen::Index> first_row;
  for (Eigen::Index i = 0; i < r.w.rows(); ++i) {
    Eigen::Index g = static_cast<Eigen::Index>(first_row.size());
    for (std::size_t k = 0; k < first_row.size(); ++k) {
      if ((r.w.row(i) - r.w.row(first_row[k])).cwiseAbs().maxCoeff() <=
          1e-12 * (1.0 + r.w.row(i).cwiseAbs().maxCoeff())) {
        g = static_cast<Eigen::Index>(k);
        break;
      }
    }
    if (g == static_cast<Eigen::Index>(first_row.size())) first_row.push_back(i);
    group_of[static_cast<std::size_t>(i)] = g;
  }
  const auto groups = static_cast<Eigen::Index>(first_row.size());
  CMatrix indicators = CMatrix::Zero(r.w.rows(), groups);
  for (std::size_t i = 0; i < group_of.size(); ++i) indicators(static_cast<Eigen::Index>(i), group_of[i]) = 1.0;
  const CMatrix base = base_design(r.w);
  const auto c = extra_terms_test(r.y, base, [&](Eigen::Index) { return indicators; });
  if (!c) {
    t.needs =
        "repeated readings (a run read twice or more, or two runs of equal masses) and more distinct runs "
        "than planes + 1";
    return t;
  }
  t.ran = true;
  t.p_value = c->p_value;
  t.residual_before = rms(c->rss_before, r.y.size());
  t.residual_after = rms(c->rss_after, r.y.size());
  t.finding = fmt::format(
      "the runs' readings depart from the linear model by more than their repeats scatter (residual RMS {} against "
      "the repeats' {})",
      significant(*t.residual_before, 3), significant(*t.residual_after, 3));
  return t;
}

// A term that may be missing from the linear model: its extra columns per sensor on the
// calibration rows and on the check rows.
struct Candidate {
  std::string name, needs;
  std::vector<CMatrix> cal, check;  // per sensor
};

// Ramsey's RESET column: the linear fit's values times their squared size (scaled by the
// calibration rows' mean square), on calibration and check rows.
Candidate amplitude_term(const Rows& r) {
  Candidate c{"amplitude nonlinearity",
              "more runs than planes + 2, with masses of different sizes (a mass ladder: one angle, 1x, 2x, 3x)",
              {},
              {}};
  const CMatrix base = base_design(r.w), base_check = base_design(r.check_w);
  for (Eigen::Index s = 0; s < r.y.cols(); ++s) {
    const CVector beta = fit(base, r.y.col(s)).beta;
    const CVector fitted = base * beta, fitted_check = base_check * beta;
    const double scale = fitted.squaredNorm() / static_cast<double>(std::max<Eigen::Index>(fitted.size(), 1));
    c.cal.push_back(fitted.cwiseProduct(fitted.cwiseAbs2().cast<Phasor>()) / scale);
    c.check.push_back(fitted_check.cwiseProduct(fitted_check.cwiseAbs2().cast<Phasor>()) / scale);
  }
  return c;
}

// The masses' mirror images conj(w), for the planes whose masses take two or more angles (at
// one angle, conj(w) is w turned and adds no column).
Candidate mirror_term(const Rows& r) {
  Candidate c{
      "phase sense", "two or more trial masses at different angles in a plane, and a run more than that", {}, {}};
  std::vector<Eigen::Index> planes;
  for (Eigen::Index p = 0; p < r.w.cols(); ++p) {
    std::optional<double> angle;
    bool two = false;
    for (Eigen::Index i = 0; i < r.w.rows(); ++i) {
      if (std::abs(r.w(i, p)) == 0.0) continue;
      const double a = std::arg(r.w(i, p));
      if (angle && std::abs(std::remainder(a - *angle, std::numbers::pi)) > 1e-6) two = true;
      angle = a;
    }
    if (two) planes.push_back(p);
  }
  CMatrix cal(r.w.rows(), static_cast<Eigen::Index>(planes.size()));
  CMatrix check(r.check_w.rows(), static_cast<Eigen::Index>(planes.size()));
  for (std::size_t j = 0; j < planes.size(); ++j) {
    cal.col(static_cast<Eigen::Index>(j)) = r.w.col(planes[j]).conjugate();
    check.col(static_cast<Eigen::Index>(j)) = r.check_w.col(planes[j]).conjugate();
  }
  c.cal.assign(static_cast<std::size_t>(r.y.cols()), cal);
  c.check.assign(static_cast<std::size_t>(r.y.cols()), check);
  return c;
}

// Superposition: products of two planes' masses w_p w_q (scaled by the mean mass squared), zero
// on every run that loads one plane: do runs with masses in two planes read as the sum of the
// single-plane responses?
Candidate superposition_term(const Rows& r) {
  Candidate c{"superposition",
              "runs with masses in two planes at once, more of them than the pairs of planes, beside single-plane runs",
              {},
              {}};
  double scale = 0.0;
  for (Eigen::Index i = 0; i < r.w.size(); ++i) scale += std::abs(r.w(i));
  scale = scale > 0.0 ? scale / static_cast<double>(r.w.size()) : 1.0;
  const Eigen::Index pairs = r.w.cols() * (r.w.cols() - 1) / 2;
  CMatrix cal(r.w.rows(), pairs), check(r.check_w.rows(), pairs);
  Eigen::Index k = 0;
  for (Eigen::Index p = 0; p < r.w.cols(); ++p) {
    for (Eigen::Index q = p + 1; q < r.w.cols(); ++q, ++k) {
      cal.col(k) = r.w.col(p).cwiseProduct(r.w.col(q)) / (scale * scale);
      check.col(k) = r.check_w.col(p).cwiseProduct(r.check_w.col(q)) / (scale * scale);
    }
  }
  c.cal.assign(static_cast<std::size_t>(r.y.cols()), cal);
  c.check.assign(static_cast<std::size_t>(r.y.cols()), check);
  return c;
}

CMatrix joined(const CMatrix& a, const CMatrix& b) {
  CMatrix out(a.rows(), a.cols() + b.cols());
  out << a, b;
  return out;
}

// What a significant mirror term means: the declared sense is wrong where the mirror-image model
// alone fits (a quarter of the residual or less), else some masses' angles are not as written.
std::string mirror_finding(const Rows& r, const ModelTest& t) {
  CMatrix mirror(r.w.rows(), r.w.cols() + 1);
  mirror << CMatrix::Ones(r.w.rows(), 1), r.w.conjugate();
  double mirror_rss = 0.0, base_rss = 0.0;
  for (Eigen::Index s = 0; s < r.y.cols(); ++s) {
    mirror_rss += fit(mirror, r.y.col(s)).rss;
    base_rss += fit(base_design(r.w), r.y.col(s)).rss;
  }
  if (mirror_rss < 0.25 * base_rss) {
    return fmt::format(
        "the readings follow the masses' mirror images (residual RMS {} against {} as declared): phases and masses' "
        "angles count in opposite senses; declare the other phase sense (phase = \"lag\" or \"lead\") or the other "
        "weight_angles (\"with_rotation\" or \"against_rotation\")",
        significant(rms(mirror_rss, r.y.size()), 3), significant(rms(base_rss, r.y.size()), 3));
  }
  return fmt::format(
      "the readings depend on the masses' mirror images as well (residual RMS {} -> {}): a response that is not "
      "linear in the masses (an orbit distorted by a nonlinear support), or a mass placed or written at another angle "
      "than declared",
      significant(*t.residual_before, 3), significant(*t.residual_after, 3));
}

// Forward selection: the most significant missing term is added, the others tested again beside
// it, until none is significant at the family level (Bonferroni over the terms that can be tested).
std::vector<ModelTest> select_terms(const Rows& r, std::vector<Candidate> candidates) {
  std::vector<ModelTest> out(candidates.size());
  std::vector<CMatrix> current(static_cast<std::size_t>(r.y.cols()), base_design(r.w));
  std::vector<CMatrix> current_check(static_cast<std::size_t>(r.y.cols()), base_design(r.check_w));
  std::vector<bool> open(candidates.size(), true);
  std::size_t testable = 0;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    out[k].name = candidates[k].name;
    const auto& cand = candidates[k];
    const auto c = extra_terms_test(r.y, current.front(), [&](Eigen::Index s) {
      return joined(current[static_cast<std::size_t>(s)], cand.cal[static_cast<std::size_t>(s)]);
    });
    if (!c) {
      out[k].needs = cand.needs;
      open[k] = false;
      continue;
    }
    out[k].ran = true;
    ++testable;
  }
  const double level = kModelTestLevel / static_cast<double>(std::max<std::size_t>(testable, 1));
  for (;;) {
    std::optional<std::size_t> best;
    std::optional<Combined> best_c;
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      if (!open[k]) continue;
      const auto& cand = candidates[k];
      const auto c = extra_terms_test(r.y, current.front(), [&](Eigen::Index s) {
        return joined(current[static_cast<std::size_t>(s)], cand.cal[static_cast<std::size_t>(s)]);
      });
      if (!c) {  // beside the terms already added, no degrees of freedom are left for it
        open[k] = false;
        out[k].ran = false;
        out[k].p_value.reset();
        out[k].needs = "a run more: beside the term found, no degrees of freedom are left to test it";
        continue;
      }
      out[k].p_value = c->p_value;
      if (!best || c->p_value < *out[*best].p_value) {
        best = k;
        best_c = c;
      }
    }
    if (!best || *out[*best].p_value >= level) break;
    ModelTest& t = out[*best];
    const Candidate& cand = candidates[*best];
    t.significant = true;
    open[*best] = false;
    t.residual_before = rms(best_c->rss_before, r.y.size());
    t.residual_after = rms(best_c->rss_after, r.y.size());
    if (r.check_w.rows() > 0) {
      double before = 0.0, after = 0.0;
      for (Eigen::Index s = 0; s < r.y.cols(); ++s) {
        const auto su = static_cast<std::size_t>(s);
        const CVector b0 = fit(current[su], r.y.col(s)).beta;
        before += (r.check_y.col(s) - current_check[su] * b0).squaredNorm();
        after += (r.check_y.col(s) - joined(current_check[su], cand.check[su]) * best_c->after[su].beta).squaredNorm();
      }
      t.check_before = rms(before, r.check_y.size());
      t.check_after = rms(after, r.check_y.size());
    }
    for (std::size_t s = 0; s < current.size(); ++s) {
      current[s] = joined(current[s], cand.cal[s]);
      current_check[s] = joined(current_check[s], cand.check[s]);
    }
    t.finding = cand.name == "phase sense" ? mirror_finding(r, t)
                : cand.name == "superposition"
                    ? fmt::format(
                          "runs with masses in two planes do not read as the sum of "
                          "the single-plane responses: a term w_p w_q takes the "
                          "residual RMS from {} to {}",
                          significant(*t.residual_before, 3), significant(*t.residual_after, 3))
                    : fmt::format(
                          "the readings' gain changes with their size (a support that stiffens or softens, a "
                          "sensor that saturates): a term y|y|^2 takes the residual RMS from {} to {}",
                          significant(*t.residual_before, 3), significant(*t.residual_after, 3));
  }
  return out;
}

// The declared model against its mirror image [1, conj(w)] (as many terms: a non-nested
// comparison): the ratio of their residuals, pooled over sensors, against F(2 nu, 2 nu) as if the
// two were independent fits of the same noise. A mirror image that fits far better means the
// declared senses disagree; every other test of the declared model is then moot.
std::optional<ModelTest> wrong_sense(const Rows& r, double level) {
  CMatrix mirror(r.w.rows(), r.w.cols() + 1);
  mirror << CMatrix::Ones(r.w.rows(), 1), r.w.conjugate();
  const CMatrix base = base_design(r.w);
  double declared_rss = 0.0, mirror_rss = 0.0;
  Eigen::Index nu = 0;
  for (Eigen::Index s = 0; s < r.y.cols(); ++s) {
    const Fit f0 = fit(base, r.y.col(s)), f1 = fit(mirror, r.y.col(s));
    if (f0.rank != f1.rank || r.y.rows() - f0.rank <= 0) return std::nullopt;
    declared_rss += f0.rss;
    mirror_rss += f1.rss;
    nu += r.y.rows() - f0.rank;
  }
  if (!(mirror_rss > 0.0) || declared_rss < 4.0 * mirror_rss) return std::nullopt;
  const double ratio = declared_rss / mirror_rss, dof = 2.0 * static_cast<double>(nu);
  const double p = boost::math::cdf(boost::math::complement(boost::math::fisher_f(dof, dof), ratio));
  if (p >= level) return std::nullopt;
  ModelTest t;
  t.name = "phase sense";
  t.ran = t.significant = true;
  t.p_value = p;
  t.residual_before = rms(declared_rss, r.y.size());
  t.residual_after = rms(mirror_rss, r.y.size());
  t.finding = mirror_finding(r, t);
  return t;
}

}  // namespace

std::vector<ModelTest> test_linear_model(const std::vector<BalancingRun>& runs, std::size_t planes) {
  const Rows r = rows_of(runs, planes);
  std::vector<ModelTest> tests = {lack_of_fit(r)};
  if (tests[0].ran) tests[0].significant = *tests[0].p_value < kModelTestLevel;
  if (!tests[0].significant) tests[0].finding.clear();  // a finding is said only where there is one
  if (auto sense = wrong_sense(r, kModelTestLevel / 2.0)) {
    ModelTest amplitude;
    amplitude.name = "amplitude nonlinearity";
    amplitude.needs = "the phase sense set right first: the readings follow the masses' mirror images";
    ModelTest superposition = amplitude;
    superposition.name = "superposition";
    tests.push_back(std::move(amplitude));
    tests.push_back(std::move(superposition));
    tests.push_back(std::move(*sense));
    return tests;
  }
  for (auto& t : select_terms(r, {amplitude_term(r), mirror_term(r), superposition_term(r)})) {
    tests.push_back(std::move(t));
  }
  return tests;
}

}  // namespace poise::estimators
