#include "engine/results/confidence_bound.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <boost/math/special_functions/beta.hpp>

#include "core/error.h"
#include "core/format.h"
#include "engine/kind_interface/study_evaluation.h"
#include "sampling/statistics.h"

namespace poise::engine {
namespace {

// q of "p99.73" / "p99_73" (as a fraction), or nullopt for another statistic.
std::optional<double> quantile_level(const std::string& stat) {
  if (stat.size() < 2 || stat[0] != 'p' || !is_statistic(stat)) return std::nullopt;
  std::string q = stat.substr(1);
  std::replace(q.begin(), q.end(), '_', '.');
  return std::stod(q) / 100.0;
}

bool is_fraction(const std::string& stat) { return stat.rfind("fraction_", 0) == 0; }

// Smallest x with P(B <= x) >= c for B ~ Binomial(n, q).
double binomial_quantile_up(double n, double q, double c) {
  boost::math::binomial_distribution<double> bin(n, q);
  double x = std::floor(boost::math::quantile(bin, c));
  while (x < n && boost::math::cdf(bin, x) < c) x += 1.0;
  while (x > 0 && boost::math::cdf(bin, x - 1.0) >= c) x -= 1.0;
  return x;
}

// Order-statistic bound of the q-quantile at one-sided confidence c (0-based index), if any.
std::optional<double> order_statistic_bound(std::vector<double> v, double q, bool upper, double c) {
  const double n = static_cast<double>(v.size());
  if (v.empty()) return std::nullopt;
  std::sort(v.begin(), v.end());
  if (upper) {
    // P(X_(k) >= xi_q) = P(B <= k - 1) >= c.
    const double x = binomial_quantile_up(n, q, c);
    if (x + 1.0 > n || boost::math::cdf(boost::math::binomial_distribution<double>(n, q), x) < c) return std::nullopt;
    return v[static_cast<std::size_t>(x)];
  }
  // P(X_(k) <= xi_q) = P(B >= k) = 1 - P(B <= k - 1) >= c: the largest k with P(B <= k-1) <= 1-c.
  boost::math::binomial_distribution<double> bin(n, q);
  if (boost::math::cdf(bin, 0.0) > 1.0 - c) return std::nullopt;
  double x = binomial_quantile_up(n, q, 1.0 - c);  // smallest with cdf >= 1 - c
  if (boost::math::cdf(bin, x) > 1.0 - c) x -= 1.0;
  while (x + 1.0 < n && boost::math::cdf(bin, x + 1.0) <= 1.0 - c) x += 1.0;
  return v[static_cast<std::size_t>(x)];  // X_(x + 1), 1-based
}

double t_quantile(double dof, double c) { return boost::math::quantile(boost::math::students_t(dof), c); }

double mean_of(const std::vector<double>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

double sd_of(const std::vector<double>& v) {
  const double m = mean_of(v);
  double s = 0.0;
  for (double x : v) s += (x - m) * (x - m);
  return v.size() > 1 ? std::sqrt(s / static_cast<double>(v.size() - 1)) : 0.0;
}

// Per-replicate statistics (replicates with >= 2 values).
std::vector<double> per_replicate(const SampleSet& s, const std::string& stat) {
  std::map<std::size_t, std::vector<double>> groups;
  for (std::size_t i = 0; i < s.values.size(); ++i) groups[s.replicate[i]].push_back(s.values[i]);
  std::vector<double> out;
  for (const auto& [r, g] : groups) {
    if (g.size() >= 2) out.push_back(statistic(g, stat));
  }
  return out;
}

// Clopper-Pearson bounds of k successes in n at one-sided confidence c.
double clopper_pearson_lower(double k, double n, double c) {
  return k <= 0 ? 0.0 : boost::math::ibeta_inv(k, n - k + 1.0, 1.0 - c);
}
double clopper_pearson_upper(double k, double n, double c) {
  return k >= n ? 1.0 : boost::math::ibeta_inv(k + 1.0, n - k, c);
}

}  // namespace

BoundSpec parse_bound(const std::string& text) {
  BoundSpec b;
  if (text == "value") return b;
  std::string rest;
  if (text.rfind("upper", 0) == 0) {
    b.side = BoundSide::kUpper;
    rest = text.substr(5);
  } else if (text.rfind("lower", 0) == 0) {
    b.side = BoundSide::kLower;
    rest = text.substr(5);
  }
  double c = NAN;
  std::size_t used = 0;
  try {
    c = std::stod(rest, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (b.side == BoundSide::kNone || used == 0 || used != rest.size() || !(c > 50.0 && c < 100.0)) {
    throw Error("\"" + text +
                "\" is not a bound; expected \"value\", \"upper<c>\" or \"lower<c>\" with the "
                "one-sided confidence c in percent, 50 < c < 100 (e.g. \"upper95\")");
  }
  b.confidence = c / 100.0;
  return b;
}

std::string to_string(const BoundSpec& b) {
  if (b.side == BoundSide::kNone) return "value";
  return fmt::format("{}{:g}", b.side == BoundSide::kUpper ? "upper" : "lower", 100.0 * b.confidence);
}

std::string describe(const BoundSpec& b) {
  if (b.side == BoundSide::kNone) return "point value";
  return fmt::format("{} {:g}% bound", b.side == BoundSide::kUpper ? "upper" : "lower", 100.0 * b.confidence);
}

bool bound_supported(const std::string& stat) {
  return stat == "mean" || quantile_level(stat).has_value() || (is_fraction(stat) && is_statistic(stat));
}

std::size_t SampleSet::replicates() const {
  if (replicate.empty()) return 0;
  std::map<std::size_t, std::size_t> count;
  for (std::size_t r : replicate) ++count[r];
  std::size_t n = 0;
  for (const auto& [r, c] : count) n += c >= 2 ? 1 : 0;
  return n;
}

SampleSet sample_set(const std::vector<double>& values, const std::vector<std::size_t>& ok_index,
                     std::size_t replicate_size) {
  SampleSet s;
  s.values = values;
  if (replicate_size > 0 && ok_index.size() == values.size()) {
    s.replicate.reserve(values.size());
    for (std::size_t i : ok_index) s.replicate.push_back(i / replicate_size);
  }
  return s;
}

std::optional<double> one_sided_bound(const SampleSet& s, const std::string& stat, const BoundSpec& b) {
  if (b.side == BoundSide::kNone) return statistic(s.values, stat);
  if (s.values.empty() || stat == "min" || stat == "max") return std::nullopt;
  const bool upper = b.side == BoundSide::kUpper;
  const double c = b.confidence;
  if (!s.replicate.empty()) {
    // A quantile by Woodruff's method (sampling/statistics.h), not the spread of each
    // replicate's own quantile, which for p99.73 of a replicate of 1024 is near its maximum.
    if (const auto q = quantile_level(stat)) {
      return sampling::replicate_quantile_bound(s.values, s.replicate, *q, c, upper);
    }
    const std::vector<double> per = per_replicate(s, stat);
    if (per.size() < 2) return std::nullopt;
    const double half =
        t_quantile(static_cast<double>(per.size() - 1), c) * sd_of(per) / std::sqrt(static_cast<double>(per.size()));
    const double pooled = statistic(s.values, stat);
    return upper ? pooled + half : pooled - half;
  }
  const double n = static_cast<double>(s.values.size());
  if (const auto q = quantile_level(stat)) return order_statistic_bound(s.values, *q, upper, c);
  if (stat == "mean") {
    if (s.values.size() < 2) return std::nullopt;
    const double half = t_quantile(n - 1.0, c) * sd_of(s.values) / std::sqrt(n);
    return upper ? mean_of(s.values) + half : mean_of(s.values) - half;
  }
  if (is_fraction(stat)) {
    const double k = std::round(statistic(s.values, stat) * n);
    return upper ? clopper_pearson_upper(k, n, c) : clopper_pearson_lower(k, n, c);
  }
  if (stat == "std" && s.values.size() >= 2) {
    const double v = sd_of(s.values), dof = n - 1.0;
    boost::math::chi_squared chi(dof);
    return upper ? v * std::sqrt(dof / boost::math::quantile(chi, 1.0 - c))
                 : v * std::sqrt(dof / boost::math::quantile(chi, c));
  }
  return std::nullopt;
}

Interval interval(const SampleSet& s, const std::string& stat, double confidence) {
  Interval r;
  r.value = statistic(s.values, stat);
  const double one_sided = 1.0 - (1.0 - confidence) / 2.0;
  if (stat == "min" || stat == "max") {
    r.method = "sample " + stat + ", no interval";
    return r;
  }
  r.lo = one_sided_bound(s, stat, {BoundSide::kLower, one_sided});
  r.hi = one_sided_bound(s, stat, {BoundSide::kUpper, one_sided});
  if (!s.replicate.empty()) {
    r.method = fmt::format("{} replicates", s.replicates());
  } else if (quantile_level(stat)) {
    r.method = "order statistics";
  } else if (stat == "mean") {
    r.method = "Student t";
  } else if (is_fraction(stat)) {
    r.method = "Clopper-Pearson";
  } else {
    r.method = "chi-square (normal values)";
  }
  return r;
}

}  // namespace poise::engine
