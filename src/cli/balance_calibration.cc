#include "cli/balance_calibration.h"

#include <cmath>
#include <limits>
#include <map>

#include <fmt/format.h>
#include <Eigen/Dense>
#include <boost/math/distributions/students_t.hpp>
#include <boost/math/tools/minima.hpp>

#include "cli/balance_design.h"
#include "core/error.h"
#include "core/format.h"
#include "engine/kind_interface/output_spec.h"
#include "engine/kind_interface/study_kind.h"

namespace poise::cli {
namespace {

// One real coefficient and the study's output it is fitted with (both in the output's unit).
struct Target {
  const balancing::DesignCompare* compare = nullptr;
  std::string unit;
  double real = 0.0, real_se = 0.0;
};

// The study's means at one value of the key, the covariance of one machine's figures about them,
// and chi2 against the targets.
struct Means {
  double chi2 = std::numeric_limits<double>::infinity();
  Eigen::VectorXd mean;
  Eigen::MatrixXd weight;  // the inverse of the residuals' covariance
};

Means means_of(const engine::McResult& sim, const std::vector<Target>& targets) {
  Means m;
  const auto k = static_cast<Eigen::Index>(targets.size());
  std::vector<const std::vector<double>*> columns;
  for (const Target& t : targets) columns.push_back(&sim.values[sim.index(t.compare->output)]);
  const std::size_t n = columns.front()->size();
  if (n <= targets.size() + 2) return m;  // too few machines for a covariance: this value cannot be judged
  Eigen::MatrixXd x(static_cast<Eigen::Index>(n), k);
  for (Eigen::Index j = 0; j < k; ++j) {
    for (std::size_t i = 0; i < n; ++i) x(static_cast<Eigen::Index>(i), j) = (*columns[static_cast<std::size_t>(j)])[i];
  }
  m.mean = x.colwise().mean().transpose();
  const Eigen::MatrixXd centred = x.rowwise() - m.mean.transpose();
  // The real machine is one machine as built: its figures scatter about the study's mean by the
  // machines' own covariance, plus the study's error of its mean (1 / n) and the readings' errors.
  Eigen::MatrixXd cov =
      centred.transpose() * centred / static_cast<double>(n - 1) * (1.0 + 1.0 / static_cast<double>(n));
  Eigen::VectorXd r(k);
  for (Eigen::Index j = 0; j < k; ++j) {
    const Target& t = targets[static_cast<std::size_t>(j)];
    cov(j, j) += t.real_se * t.real_se;
    r(j) = m.mean(j) - t.real;
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(cov);
  if (ldlt.info() != Eigen::Success || ldlt.rcond() < 1e-12) return m;
  // The inverse of a covariance estimated from n machines is too large on average by
  // (n - 1) / (n - k - 2) (the inverse Wishart's mean): scaled back, or the standard error would
  // be too small (at 16 machines and 4 figures, 75% coverage instead of 95%).
  m.weight = ldlt.solve(Eigen::MatrixXd::Identity(k, k)) * (static_cast<double>(n) - static_cast<double>(k) - 2.0) /
             (static_cast<double>(n) - 1.0);
  m.chi2 = r.dot(m.weight * r);
  return m;
}

std::vector<Target> targets_of(const balancing::BalancingCampaign& c, const balancing::CampaignAnalysis& a,
                               const std::vector<engine::OutputSpec>& outputs) {
  std::vector<Target> targets;
  for (const auto& k : c.design->compare) {
    if (k.figure != "influence") continue;
    Target t;
    t.compare = &k;
    t.unit = engine::output_unit_of(outputs, k.output);
    const double scale = engine::unit_quantity(t.unit).value;
    const RealCoefficient r = real_influence(c, a, k);
    t.real = r.value / scale;
    t.real_se = r.se / scale;
    targets.push_back(t);
  }
  return targets;
}

std::string sentence_of(const balancing::DesignCalibration& d) {
  const std::string unit = d.unit.empty() ? "" : " " + d.unit;
  return fmt::format(
      "{} calibrated to {}{} (standard error {}{}) on {} real influence coefficient(s): chi-squared {} with the "
      "model's own value, {} after ({} degree(s) of freedom){}; a calibration to these readings, not a validation",
      d.key, significant(d.value, 5), unit, significant(d.se, 2), unit, d.figures.size(), significant(d.chi2_before, 3),
      significant(d.chi2_after, 3), d.dof,
      d.at_bound ? " (at an end of the range: widen it, the best value may lie beyond)" : "");
}

// 1 / sqrt(g' S^-1 g), the means' slopes g between `lo` and `hi` (the key's values), S^-1 at the
// fitted value `m`; infinite where the slopes say nothing.
// The covariance comes from n machines, not from the truth: value +- 1.96 se is made the 95%
// interval of Student's t with n - k degrees of freedom (at 16 machines and 4 figures the plain
// 1.96 covered 90% of 300 simulated machines, at 32 machines 96%).
double standard_error(const Means& m_lo, const Means& m_hi, double lo, double hi, const Means& m, std::size_t n) {
  if (m_lo.mean.size() != m.mean.size() || m_hi.mean.size() != m.mean.size() || m.weight.size() == 0) {
    return std::numeric_limits<double>::infinity();
  }
  const Eigen::VectorXd slope = (m_hi.mean - m_lo.mean) / (hi - lo);
  const double information = slope.dot(m.weight * slope);
  if (!(information > 0.0)) return std::numeric_limits<double>::infinity();
  const double nu = static_cast<double>(n) - static_cast<double>(m.mean.size());
  return boost::math::quantile(boost::math::students_t(nu), 0.975) / 1.959963984540054 / std::sqrt(information);
}

// Each real coefficient beside the study's mean before (as_is) and after (at the fitted value).
std::vector<balancing::CalibrationFigure> figures_of(const std::vector<Target>& targets, const Means& before,
                                                     const Means& after) {
  std::vector<balancing::CalibrationFigure> figures;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const Target& t = targets[i];
    balancing::CalibrationFigure f;
    f.sensor = t.compare->sensor;
    f.plane = t.compare->plane;
    f.output = t.compare->output;
    f.unit = t.unit;
    f.real = t.real;
    f.real_se = t.real_se;
    const auto j = static_cast<Eigen::Index>(i);
    f.before = j < before.mean.size() ? before.mean(j) : NAN;
    f.after = j < after.mean.size() ? after.mean(j) : NAN;
    figures.push_back(f);
  }
  return figures;
}

}  // namespace

balancing::DesignCalibration calibrate_design(const balancing::BalancingCampaign& c,
                                              const balancing::CampaignAnalysis& a, const engine::StudyConfig& cfg,
                                              const engine::McResult& as_is, int threads) {
  const balancing::DesignCalibrate& k = *c.design->calibrate;
  const engine::StudyKind& kind = engine::study_kind(cfg.kind);
  const std::vector<Target> targets = targets_of(c, a, kind.outputs(cfg));
  if (c.design->samples <= targets.size() + 2) {
    throw Error(
        fmt::format("{}:{}: [design.calibrate]: [design] samples = {} cannot give the covariance of {} "
                    "figures; expected more than {} (at least 32: with 16 machines the intervals covered 92%)",
                    c.file, k.line, c.design->samples, targets.size(), targets.size() + 2));
  }
  balancing::DesignCalibration d;
  d.key = k.key;
  d.unit = k.unit;
  d.low = k.low;
  d.high = k.high;
  std::map<double, Means> seen;
  auto at = [&](double v) -> const Means& {
    auto it = seen.find(v);
    if (it != seen.end()) return it->second;
    const std::map<std::string, std::string> override{
        {k.key, fmt::format("{:.17g}{}{}", v, k.unit.empty() ? "" : " ", k.unit)}};
    try {
      const engine::McResult sim = kind.evaluate(cfg, override, c.design->samples, cfg.seed, threads);
      ++d.evaluations;
      return seen.emplace(v, means_of(sim, targets)).first->second;
    } catch (const Error& e) {
      throw Error(fmt::format("{}:{}: [design.calibrate] {} = {}: the design study cannot be run there: {}", c.file,
                              k.line, k.key, override.begin()->second, e.what()));
    }
  };
  const Means before = means_of(as_is, targets);
  std::uintmax_t iterations = 60;
  const auto best =
      boost::math::tools::brent_find_minima([&](double v) { return at(v).chi2; }, k.low, k.high, 24, iterations);
  d.value = best.first;
  d.chi2_before = before.chi2;
  d.chi2_after = best.second;
  const double width = k.high - k.low;
  d.at_bound = d.value - k.low < 1e-3 * width || k.high - d.value < 1e-3 * width;
  // Standard error from the slopes of the means (central differences within the range).
  const double step = 1e-2 * width;
  const double lo = std::max(k.low, d.value - step), hi = std::min(k.high, d.value + step);
  const Means& m = at(d.value);
  d.dof = targets.size() - 1;
  d.se = standard_error(at(lo), at(hi), lo, hi, m, c.design->samples);
  d.figures = figures_of(targets, before, m);
  d.sentence = sentence_of(d);
  return d;
}

}  // namespace poise::cli
