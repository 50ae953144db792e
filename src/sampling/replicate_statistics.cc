// Summary statistics of randomized replicates (statistics.h summarize_replicates): the mean
// and std from the spread of the replicates' own figures, the quantiles by Woodruff's method.
#include <algorithm>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>

#include "core/error.h"
#include "core/format.h"
#include "sampling/statistics.h"

namespace poise::sampling {

namespace {

double t975(std::size_t replicates) {
  return boost::math::quantile(boost::math::students_t(static_cast<double>(replicates - 1)), 0.975);
}

// Mean and standard error of the mean of x.
std::pair<double, double> mean_and_se(const std::vector<double>& x) {
  const double r = static_cast<double>(x.size());
  double mean = 0.0, m2 = 0.0;
  for (double v : x) mean += v;
  mean /= r;
  for (double v : x) m2 += (v - mean) * (v - mean);
  return {mean, std::sqrt(m2 / (r - 1.0) / r)};
}

// Woodruff's ends of the p-quantile: the replicates' shares below the pooled estimate q give
// the interval p -+ t_quantile x se of F(q), mapped back through the pooled order statistics
// (1-based ranks by definition 8, rounded outwards: the interval keeps at least the order
// statistics around the estimate when the replicates agree exactly).
struct Ends {
  std::optional<double> lo, hi;
  double half = 0.0;
};
Ends woodruff_ends(double p, double q, double t_quantile, const std::vector<double>& sorted,
                   const std::vector<std::vector<double>>& groups) {
  std::vector<double> share;
  for (const auto& g : groups) {
    double below = 0.0;
    for (double v : g) below += v < q ? 1.0 : v == q ? 0.5 : 0.0;
    share.push_back(below / static_cast<double>(g.size()));
  }
  Ends e;
  e.half = t_quantile * mean_and_se(share).second;
  const double n = static_cast<double>(sorted.size());
  auto rank = [&](double pp) { return (n + 1.0 / 3.0) * pp + 1.0 / 3.0; };
  const double lo_rank = std::floor(rank(p - e.half)), hi_rank = std::ceil(rank(p + e.half));
  if (lo_rank >= 1.0) e.lo = sorted[static_cast<std::size_t>(lo_rank) - 1];
  if (hi_rank <= n) e.hi = sorted[static_cast<std::size_t>(hi_rank) - 1];
  return e;
}

// The replicates of 2 or more values.
std::vector<std::vector<double>> replicate_groups(std::span<const double> values,
                                                  std::span<const std::size_t> replicate_of) {
  POISE_INVARIANT(values.size() == replicate_of.size(), "one replicate number per value");
  std::vector<std::vector<double>> all;
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (all.size() <= replicate_of[k]) all.resize(replicate_of[k] + 1);
    all[replicate_of[k]].push_back(values[k]);
  }
  std::erase_if(all, [](const std::vector<double>& g) { return g.size() < 2; });
  return all;
}

// Woodruff's 95% interval of the p-quantile into e (whose value is the pooled estimate).
void woodruff(Estimate& e, double p, const std::vector<double>& sorted, const std::vector<std::vector<double>>& groups,
              double replicate_size) {
  const Ends ends = woodruff_ends(p, e.value, t975(groups.size()), sorted, groups);
  e.lo = ends.lo;
  e.hi = ends.hi;
  const double half = ends.half;
  std::string name = "p";  // appended: "p" + a temporary trips GCC 12's -Wrestrict (PR 105329)
  name += significant(100.0 * p);
  if (!e.hi || !e.lo) {
    e.note = std::string("one-sided: the replicates' spread of the share below ") + name + " (+-" +
             significant(half, 2) + ") reaches past the " + (e.hi ? "smallest" : "largest") + " of the " +
             std::to_string(sorted.size()) + " samples; no " + (e.hi ? "lower" : "upper") + " bound";
  }
  const double tail = replicate_size * std::min(p, 1.0 - p);
  if (tail < kMinTailPerReplicate) {
    e.note += std::string(e.note.empty() ? "" : "; ") + "approximate: replicate_size x " + (p > 0.5 ? "(1 - p)" : "p") +
              " = " + significant(tail, 3) + " < " + fixed(kMinTailPerReplicate, 0) +
              ", so each replicate holds only a few samples beyond " + name +
              " and their spread is a spread of small counts; use replicates of at least " +
              fixed(std::ceil(kMinTailPerReplicate / std::min(p, 1.0 - p)), 0) + " samples for this figure";
  }
}

}  // namespace

std::optional<double> replicate_quantile_bound(std::span<const double> values,
                                               std::span<const std::size_t> replicate_of, double p, double confidence,
                                               bool upper) {
  const std::vector<std::vector<double>> groups = replicate_groups(values, replicate_of);
  if (groups.size() < 2) return std::nullopt;
  std::vector<double> sorted(values.begin(), values.end());
  std::sort(sorted.begin(), sorted.end());
  const double q = quantile_sorted(sorted, p).value;
  const double t = boost::math::quantile(boost::math::students_t(static_cast<double>(groups.size() - 1)), confidence);
  const Ends e = woodruff_ends(p, q, t, sorted, groups);
  return upper ? e.hi : e.lo;
}

Summary summarize_replicates(std::span<const double> values, std::span<const std::size_t> replicate_of) {
  Summary pooled = summarize(values);
  const std::vector<std::vector<double>> groups = replicate_groups(values, replicate_of);
  std::vector<Summary> per;
  double size_sum = 0.0;
  for (const auto& g : groups) {
    per.push_back(summarize(g));
    size_sum += static_cast<double>(g.size());
  }
  const std::size_t r = per.size();
  std::vector<Estimate*> pooled_figures = {&pooled.mean, &pooled.std};
  for (const SummaryQuantile& q : summary_quantiles()) pooled_figures.push_back(&(pooled.*q.field));
  for (Estimate* e : pooled_figures) {
    e->lo.reset();
    e->hi.reset();
    e->note = r < 2 ? "no interval: fewer than 2 replicates of 2 or more values" : "";
  }
  if (r < 2) return pooled;  // max keeps its order-statistic bound
  auto by_replicates = [&](Estimate& e, Estimate Summary::*field) {
    std::vector<double> x;
    x.reserve(per.size());
    for (const auto& s : per) x.push_back((s.*field).value);
    const double half = t975(r) * mean_and_se(x).second;
    e.lo = e.value - half;
    e.hi = e.value + half;
  };
  by_replicates(pooled.mean, &Summary::mean);
  by_replicates(pooled.std, &Summary::std);
  std::vector<double> sorted(values.begin(), values.end());
  std::sort(sorted.begin(), sorted.end());
  const double m = size_sum / static_cast<double>(r);
  for (const SummaryQuantile& q : summary_quantiles()) woodruff(pooled.*q.field, q.p, sorted, groups, m);
  return pooled;
}

}  // namespace poise::sampling
