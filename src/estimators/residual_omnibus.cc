#include "estimators/residual_omnibus.h"

#include "estimators/residual_periodogram.h"

#include "core/error.h"
#include "core/format.h"

#include <Eigen/QR>
#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <map>
#include <numeric>
#include <random>

namespace poise::estimators {
namespace {

// P(X > x) for X ~ chi^2(dof). A statistic that overflowed to +inf (a declared noise level or
// standard errors many orders of magnitude below the residuals: --noise "1e-300 mN*m") lies
// beyond every quantile: 0, where Boost.Math would throw a domain error.
double chi_squared_upper_tail(double dof, double x) {
  if (std::isinf(x) && x > 0) return 0.0;
  if (!std::isfinite(x)) throw Error("the residual statistic is not a number (check --noise and the standard errors)");
  return boost::math::cdf(boost::math::complement(boost::math::chi_squared(dof), x));
}

// "row 17 (line 19, theta 160 deg, t 960 s)".
std::string at_row(const OmnibusInput& in, std::size_t i) {
  std::string s = "row " + std::to_string(i) + " (";
  if (!in.lines.empty()) s += "line " + std::to_string(in.lines[i]) + ", ";
  s += fmt::format("theta {:.4g} deg", in.theta_deg[i]);
  if (!in.time_s.empty()) s += fmt::format(", t {:.6g} s", in.time_s[i]);
  return s + ")";
}

StructureTest lack_of_fit(const OmnibusInput& in, double rss) {
  StructureTest t;
  t.name = "lack_of_fit";
  std::map<long long, std::vector<std::size_t>> groups;  // angle modulo 360 in micro-degrees
  for (std::size_t i = 0; i < in.residual.size(); ++i) {
    double a = std::fmod(in.theta_deg[i], 360.0);
    if (a < 0.0) a += 360.0;
    groups[std::llround(a * 1e6) % 360000000LL].push_back(i);
  }
  const double n = static_cast<double>(in.residual.size()), g = static_cast<double>(groups.size());
  const double p = static_cast<double>(in.parameters);
  if (!(g > p) || !(n > g)) {
    t.note = n > g ? "not examined: fewer positions than fitted columns" : "not examined: no position is repeated";
    return t;
  }
  if (in.ar) {
    t.note = "not examined: with AR(1) errors repeats are not independent";
    return t;
  }
  double ss_pe = 0.0;
  for (const auto& [key, rows] : groups) {
    double m = 0.0;
    for (std::size_t i : rows) m += in.residual[i];
    m /= static_cast<double>(rows.size());
    for (std::size_t i : rows) ss_pe += (in.residual[i] - m) * (in.residual[i] - m);
  }
  const double ss_lof = std::max(0.0, rss - ss_pe);
  if (ss_pe <= 0.0) {
    t.note = "not examined: repeats agree exactly";
    return t;
  }
  t.statistic = (ss_lof / (g - p)) / (ss_pe / (n - g));
  t.p_value = boost::math::cdf(boost::math::complement(boost::math::fisher_f(g - p, n - g), t.statistic));
  t.examined = true;
  t.note = fmt::format("{:.0f} positions, pure error on {:.0f} dof", g, n - g);
  return t;
}

StructureTest declared_noise(const OmnibusInput& in, double rss) {
  StructureTest t;
  t.name = "declared_noise";
  const double dof = static_cast<double>(in.residual.size()) - static_cast<double>(in.parameters);
  if (!in.noise_per_point.empty()) {
    double chi2 = 0.0, mean_var = 0.0;
    for (std::size_t i = 0; i < in.residual.size(); ++i) {
      chi2 += in.residual[i] * in.residual[i] / (in.noise_per_point[i] * in.noise_per_point[i]);
      mean_var += in.noise_per_point[i] * in.noise_per_point[i];
    }
    mean_var /= static_cast<double>(in.residual.size());
    t.statistic = chi2;
    t.note = fmt::format("residual sd {:.4g} against the points' own standard errors (rms {:.4g})",
                         std::sqrt(rss / dof), std::sqrt(mean_var));
  } else if (in.noise > 0.0) {
    t.statistic = rss / (in.noise * in.noise);
    t.note = fmt::format("residual sd {:.4g} against declared {:.4g}", std::sqrt(rss / dof), in.noise);
  } else {
    t.note = "not examined: no independent noise level (--noise or a torque_se column)";
    return t;
  }
  t.p_value = chi_squared_upper_tail(dof, t.statistic);
  t.examined = true;
  return t;
}

StructureTest ljung_box(const std::vector<double>& r, bool ar) {
  StructureTest t;
  t.name = "ljung_box";
  const std::size_t n = r.size();
  if (n < 12) {
    t.note = "not examined: fewer than 12 points";
    return t;
  }
  // h ~ ln n (Tsay 2010): with h = n / 4 the chi^2 tail over-rejects at n = 36 (measured 3.3 %
  // at a nominal 1.7 % over 4000 white records; 1.6 % with h = ln n).
  const std::size_t h =
      std::max<std::size_t>(2, static_cast<std::size_t>(std::lround(std::log(static_cast<double>(n)))));
  const double mean = std::accumulate(r.begin(), r.end(), 0.0) / static_cast<double>(n);
  double c0 = 0.0;
  for (double v : r) c0 += (v - mean) * (v - mean);
  if (c0 <= 0.0) {
    t.note = "not examined: the residuals are zero";
    return t;
  }
  double q = 0.0;
  for (std::size_t k = 1; k <= h; ++k) {
    double ck = 0.0;
    for (std::size_t i = k; i < n; ++i) ck += (r[i] - mean) * (r[i - k] - mean);
    const double rho = ck / c0;
    q += rho * rho / static_cast<double>(n - k);
  }
  t.statistic = static_cast<double>(n) * static_cast<double>(n + 2) * q;
  const double dof = static_cast<double>(h) - (ar ? 1.0 : 0.0);
  t.p_value = chi_squared_upper_tail(dof, t.statistic);
  t.examined = true;
  t.note = fmt::format("{:.0f} lags", static_cast<double>(h));
  return t;
}

StructureTest runs(const std::vector<double>& r) {
  StructureTest t;
  t.name = "runs";
  std::vector<int> s;
  for (double v : r) {
    if (v != 0.0) s.push_back(v > 0.0 ? 1 : -1);
  }
  const double n1 = static_cast<double>(std::count(s.begin(), s.end(), 1));
  const double n2 = static_cast<double>(s.size()) - n1;
  if (n1 < 2 || n2 < 2 || s.size() < 10) {
    t.note = "not examined: too few residuals of each sign";
    return t;
  }
  double runs_count = 1.0;
  for (std::size_t i = 1; i < s.size(); ++i) runs_count += s[i] != s[i - 1];
  const double nn = n1 + n2;
  const double mean = 2.0 * n1 * n2 / nn + 1.0;
  const double var = 2.0 * n1 * n2 * (2.0 * n1 * n2 - nn) / (nn * nn * (nn - 1.0));
  t.statistic = (runs_count - mean) / std::sqrt(var);
  t.p_value = 2.0 * boost::math::cdf(boost::math::normal(), -std::abs(t.statistic));
  t.examined = true;
  t.note = fmt::format("{:.0f} runs, {:.1f} expected", runs_count, mean);
  return t;
}

double cusum_statistic(const std::vector<double>& ordered, double dof, std::size_t* at) {
  double rss = 0.0;
  for (double v : ordered) rss += v * v;
  if (!(rss > 0.0)) return 0.0;
  const double s = std::sqrt(rss / dof);
  double sum = 0.0, best = 0.0;
  for (std::size_t k = 0; k + 1 < ordered.size(); ++k) {
    sum += ordered[k];
    if (std::abs(sum) > best) {
      best = std::abs(sum);
      if (at) *at = k;
    }
  }
  return best / (s * std::sqrt(static_cast<double>(ordered.size())));
}

// Monte Carlo p-values of the order-based tests under the design (see the header).
void monte_carlo(const OmnibusInput& in, std::vector<StructureTest>& tests) {
  constexpr int kDraws = 400;
  ResidualDraws draws(in, true, 0x5eed0b1u);
  const double dof = static_cast<double>(static_cast<Eigen::Index>(in.residual.size()) - draws.rank());
  std::vector<int> exceed(tests.size(), 0);
  std::vector<double> ordered(in.residual.size());
  for (int k = 0; k < kDraws; ++k) {
    draws.next(ordered);
    for (std::size_t t = 0; t < tests.size(); ++t) {
      StructureTest& st = tests[t];
      if (!st.examined) continue;
      double v = 0.0;
      if (st.name == "ljung_box") v = ljung_box(ordered, false).statistic;
      if (st.name == "runs") v = std::abs(runs(ordered).statistic);
      if (st.name == "cusum_step") v = cusum_statistic(ordered, dof, nullptr);
      const double obs = st.name == "runs" ? std::abs(st.statistic) : st.statistic;
      exceed[t] += v >= obs;
    }
  }
  for (std::size_t t = 0; t < tests.size(); ++t) {
    StructureTest& st = tests[t];
    if (!st.examined || (st.name != "ljung_box" && st.name != "runs" && st.name != "cusum_step")) {
      continue;
    }
    st.p_value = (1.0 + exceed[t]) / (kDraws + 1.0);
    st.note += (st.note.empty() ? "" : "; ") + std::string("Monte Carlo p under the design");
  }
}

}  // namespace

ResidualDraws::ResidualDraws(const OmnibusInput& in, bool projected, std::uint64_t seed)
    : order_(in.order), projected_(projected), z_(static_cast<Eigen::Index>(in.residual.size())), rng_(seed) {
  if (projected_) {
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(in.design);
    rank_ = qr.rank();
    q_ = qr.householderQ() * Eigen::MatrixXd::Identity(z_.size(), rank_);
  }
}

void ResidualDraws::next(std::vector<double>& ordered) {
  for (Eigen::Index i = 0; i < z_.size(); ++i) z_(i) = normal_(rng_);
  if (projected_) z_ -= q_ * (q_.transpose() * z_);
  for (std::size_t j = 0; j < ordered.size(); ++j) {
    ordered[j] = z_(static_cast<Eigen::Index>(projected_ ? order_[j] : j));
  }
}

double brownian_bridge_sup_tail(double x) {
  if (x <= 0.2) return 1.0;  // the series converges slowly here; the tail is 1 to 1e-9
  double s = 0.0;
  for (int j = 1; j <= 100; ++j) {
    const double term = std::exp(-2.0 * j * j * x * x);
    s += (j % 2 ? 2.0 : -2.0) * term;
    if (term < 1e-17) break;
  }
  return std::clamp(s, 0.0, 1.0);
}

namespace {

// The largest cumulative sum of the residual in measurement order against the Brownian
// bridge; shift_k is the position (in order) after which the level shifts most.
StructureTest cusum_step(const OmnibusInput& in, const std::vector<double>& ordered, double rss, double dof,
                         std::size_t& shift_k) {
  const std::size_t n = ordered.size();
  StructureTest cusum;
  cusum.name = "cusum_step";
  shift_k = 0;
  if (dof >= 1.0 && rss > 0.0 && n >= 8) {
    const double s = std::sqrt(rss / dof);
    double sum = 0.0, best = 0.0;
    for (std::size_t k = 0; k + 1 < n; ++k) {
      sum += ordered[k];
      if (std::abs(sum) > best) best = std::abs(sum), shift_k = k;
    }
    cusum.statistic = best / (s * std::sqrt(static_cast<double>(n)));
    cusum.p_value = brownian_bridge_sup_tail(cusum.statistic);
    cusum.examined = true;
    cusum.note = "largest after " + at_row(in, in.order[shift_k]);
  } else {
    cusum.note = "not examined: fewer than 8 points or no residual";
  }
  return cusum;
}

// Where a failing test points in the table.
std::string where_test_points(const OmnibusInput& in, const std::vector<double>& ordered, std::size_t shift_k,
                              const StructureTest& t) {
  const std::size_t n = ordered.size();
  if (t.name == "cusum_step") {
    const std::size_t a = in.order[shift_k], b = in.order[std::min(shift_k + 1, n - 1)];
    return "a level shift between " + at_row(in, a) + " and " + at_row(in, b);
  }
  if (t.name == "ljung_box" || t.name == "runs") {
    std::size_t best_a = 0, best_len = 0, a = 0;  // the longest run of one sign
    for (std::size_t k = 1; k <= n; ++k) {
      if (k == n || (ordered[k] > 0.0) != (ordered[a] > 0.0)) {
        if (k - a > best_len) best_len = k - a, best_a = a;
        a = k;
      }
    }
    return "correlated residuals in measurement order (" + t.name +
           "); longest run of one sign: " + std::to_string(best_len) + " points from " + at_row(in, in.order[best_a]) +
           " to " + at_row(in, in.order[best_a + best_len - 1]);
  }
  if (t.name == "periodogram") {
    double frequency = 1.0;
    periodogram_peak(ordered, &frequency);
    const double period = 1.0 / frequency;
    std::string s = fmt::format("a periodic component in measurement order, period {:.3g} points", period);
    if (in.time_s.size() == n && n > 1) {
      const auto [lo, hi] = std::minmax_element(in.time_s.begin(), in.time_s.end());
      s += fmt::format(" (about {:.3g} s)", period * (*hi - *lo) / static_cast<double>(n - 1));
    }
    return s;
  }
  if (t.name == "lack_of_fit") {
    return "repeated positions disagree with the model more than with each other";
  }
  return "the residual scatter exceeds the declared noise (" + t.note + ")";
}

// Where the structure is: by every test that fails at the family's level (m tests), then the
// three largest residuals.
std::string where_structure_is(const OmnibusInput& in, const std::vector<double>& ordered, std::size_t shift_k,
                               const std::vector<StructureTest>& tests, int m) {
  const std::size_t n = ordered.size();
  std::string where;
  for (const StructureTest& t : tests) {
    if (!t.examined || !(t.p_value * m < in.alpha)) continue;
    if (t.name == "runs" && where.find("correlated residuals") != std::string::npos) continue;
    where += (where.empty() ? "" : "; ") + where_test_points(in, ordered, shift_k, t);
  }
  std::vector<std::size_t> idx(n);
  std::iota(idx.begin(), idx.end(), std::size_t{0});
  std::sort(idx.begin(), idx.end(),
            [&](auto x, auto y) { return std::abs(in.residual[x]) > std::abs(in.residual[y]); });
  where += "; largest residuals at";
  for (std::size_t k = 0; k < std::min<std::size_t>(3, n); ++k) {
    where += (k ? ", " : " ") + at_row(in, idx[k]) + fmt::format(" {:+.3g}", in.residual[idx[k]]);
  }
  return where;
}

}  // namespace

OmnibusResult omnibus_check(const OmnibusInput& in) {
  OmnibusResult out;
  const std::size_t n = in.residual.size();
  std::vector<double> ordered(n);
  for (std::size_t k = 0; k < n; ++k) ordered[k] = in.residual[in.order[k]];
  double rss = 0.0;
  for (double v : in.residual) rss += v * v;
  const double dof = static_cast<double>(n) - static_cast<double>(in.parameters);

  out.tests.push_back(lack_of_fit(in, rss));
  out.tests.push_back(declared_noise(in, rss));
  out.tests.push_back(ljung_box(ordered, in.ar));
  out.tests.push_back(runs(ordered));
  std::size_t shift_k = 0;
  out.tests.push_back(cusum_step(in, ordered, rss, dof, shift_k));
  out.tests.push_back(periodogram_test(in, ordered));
  if (in.design.rows() == static_cast<Eigen::Index>(n) && in.design.cols() > 0 && !in.ar) {
    monte_carlo(in, out.tests);
  }

  // Bonferroni over the tests examined.
  int m = 0;
  const StructureTest* worst = nullptr;
  for (const StructureTest& t : out.tests) {
    if (!t.examined) continue;
    ++m;
    if (!worst || t.p_value < worst->p_value) worst = &t;
  }
  if (!worst) {
    out.message = "No structure test could be run on these points: the residual is unchecked.";
    return out;
  }
  out.p_value = std::min(1.0, m * worst->p_value);
  out.unexplained = out.p_value < in.alpha;
  if (!out.unexplained) {
    out.message = fmt::format(
        "No structure left in the residual beyond the noise (omnibus p = {:.3g}, "
        "Bonferroni over {:.0f} tests, alpha = {:.3g}).",
        out.p_value, static_cast<double>(m), in.alpha);
    return out;
  }
  out.where = where_structure_is(in, ordered, shift_k, out.tests, m);
  out.message = "Unexplained structure: " + worst->name +
                fmt::format(" p = {:.3g} (omnibus p = {:.3g})", worst->p_value, out.p_value) + " - " + out.where +
                ". No candidate effect was added for it (the candidates of the last round show how close each came, "
                "before and after the multiple-test adjustment); the unbalance estimate carries it and its "
                "standard errors, which assume independent noise, do not cover it.";
  return out;
}

}  // namespace poise::estimators
