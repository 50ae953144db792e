// Tests of the summary statistics and their 95% confidence intervals
// (src/sampling/statistics.h): exact values on known data and coverage on simulated data.
#include "sampling/statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/error.h"
#include "sampling/distribution.h"
#include "sampling/random_stream.h"

namespace {

using poise::Error;
using poise::sampling::Estimate;
using poise::sampling::RandomStream;
using poise::sampling::StreamId;
using poise::sampling::Summary;
namespace ps = poise::sampling;

constexpr double kZ975 = 1.959963984540054;  // standard normal 97.5% quantile

std::vector<double> one_to_hundred() {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i);  // unsorted on purpose
  return v;
}

TEST(Statistics, SummaryOfOneToHundred) {
  const std::vector<double> v = one_to_hundred();
  const Summary s = ps::summarize(v);
  EXPECT_EQ(s.n, 100u);
  EXPECT_NEAR(s.mean.value, 50.5, 1e-13);
  // Sample variance of 1..n: n (n + 1) / 12 = 841.6667.
  const double sd = std::sqrt(100.0 * 101.0 / 12.0);
  EXPECT_NEAR(s.std.value, sd, 1e-12);
  EXPECT_NEAR(sd * sd, 841.6667, 1e-4);
  // Mean CI: t(0.975, 99) = 1.9842169515 (tabulated), half-width t sd / 10.
  ASSERT_TRUE(s.mean.lo && s.mean.hi);
  const double half = 1.9842169515 * sd / 10.0;
  EXPECT_NEAR(*s.mean.lo, 50.5 - half, 1e-8);
  EXPECT_NEAR(*s.mean.hi, 50.5 + half, 1e-8);
  // Definition-8 quantiles: 1-based rank h = (n + 1/3) p + 1/3, linear between neighbours,
  // clamped to [1, n]; here x(i) = i, so the value is the rank itself.
  EXPECT_NEAR(s.p50.value, 50.5, 1e-12);
  EXPECT_NEAR(s.p95.value, (100.0 + 1.0 / 3.0) * 0.95 + 1.0 / 3.0, 1e-12);  // 95.65
  EXPECT_NEAR(s.p99_73.value, 100.0, 1e-12);  // rank 100.40: the maximum
  EXPECT_EQ(s.max.value, 100.0);
  // p99.73 with n = 100: the upper order statistic needed exceeds n -> no upper end, and
  // the note says the interval is one-sided and from what n it would not be.
  EXPECT_FALSE(s.p99_73.hi.has_value());
  EXPECT_TRUE(s.p99_73.lo.has_value());
  EXPECT_EQ(s.p99_73.note.rfind("one-sided: no upper bound below n = 1365", 0), 0u) << s.p99_73.note;
  EXPECT_TRUE(s.p95.note.empty()) << s.p95.note;
  EXPECT_EQ(s.max.note.rfind("one-sided", 0), 0u);
  // The maximum never has an upper end.
  EXPECT_FALSE(s.max.hi.has_value());
  ASSERT_TRUE(s.max.lo.has_value());
  EXPECT_LE(*s.max.lo, s.max.value);
  // Median CI of 1..100, the textbook distribution-free interval [x(40), x(61)]:
  // with B ~ Binomial(100, 1/2), P(x(l) > median) = P(B <= l - 1); P(B <= 39) = 0.0176 <= 2.5%
  // < P(B <= 40) = 0.0284, so l = 40; P(B <= 60) = 0.9824 >= 97.5% > P(B <= 59), so u = 61.
  ASSERT_TRUE(s.p50.lo && s.p50.hi);
  EXPECT_EQ(*s.p50.lo, 40.0);
  EXPECT_EQ(*s.p50.hi, 61.0);
  // Std CI brackets the estimate.
  ASSERT_TRUE(s.std.lo && s.std.hi);
  EXPECT_LT(*s.std.lo, sd);
  EXPECT_GT(*s.std.hi, sd);
}

// The lower tail mirrors the upper one: on 1..200 each lower quantile is n + 1 minus the upper
// one at 1 - p (definition 8 is symmetric), the minimum's interval mirrors the maximum's, and
// p0.135 has no lower end below n = 2731 (ln 0.025 / ln 0.99865: the mirror of p99.865).
TEST(Statistics, LowerTailMirrorsTheUpperTail) {
  std::vector<double> v;
  for (int i = 200; i >= 1; --i) v.push_back(i);
  const Summary s = ps::summarize(v);
  EXPECT_EQ(s.min.value, 1.0);
  EXPECT_FALSE(s.min.lo.has_value());
  ASSERT_TRUE(s.min.hi.has_value() && s.max.lo.has_value());
  EXPECT_EQ(*s.min.hi, 201.0 - *s.max.lo);
  EXPECT_EQ(s.min.note.rfind("one-sided", 0), 0u);
  EXPECT_NEAR(s.p2_5.value, 201.0 - s.p97_5.value, 1e-12);
  EXPECT_NEAR(s.p0_135.value, 201.0 - s.p99_865.value, 1e-12);
  EXPECT_NEAR(s.p2_5.value, (200.0 + 1.0 / 3.0) * 0.025 + 1.0 / 3.0, 1e-12);  // rank 5.34
  ASSERT_TRUE(s.p2_5.lo && s.p2_5.hi && s.p97_5.lo && s.p97_5.hi);
  EXPECT_EQ(*s.p2_5.lo, 201.0 - *s.p97_5.hi);
  EXPECT_EQ(*s.p2_5.hi, 201.0 - *s.p97_5.lo);
  EXPECT_FALSE(s.p0_135.lo.has_value());
  EXPECT_EQ(s.p0_135.note.rfind("one-sided: no lower bound below n = 2731", 0), 0u) << s.p0_135.note;
  // The summary from order statistics (a field read column by column) gives the same figures.
  ps::SummaryMoments m{200, 100.5, 0.0, 0.0};
  for (int i = 1; i <= 200; ++i) {
    m.m2 += (i - 100.5) * (i - 100.5);
    m.m4 += std::pow(i - 100.5, 4);
  }
  const Summary f = ps::summarize_from(m, [](std::size_t k) { return static_cast<double>(k + 1); });
  for (const ps::SummaryQuantile& q : ps::summary_quantiles()) EXPECT_EQ((f.*q.field).value, (s.*q.field).value) << q.name;
  EXPECT_EQ(f.min.value, 1.0);
}

TEST(Statistics, SmallSamples) {
  const std::vector<double> one{3.5};
  const Summary s1 = ps::summarize(one);
  EXPECT_EQ(s1.mean.value, 3.5);
  EXPECT_EQ(s1.std.value, 0.0);
  EXPECT_FALSE(s1.mean.lo.has_value());
  EXPECT_FALSE(s1.std.lo.has_value());
  EXPECT_EQ(s1.p50.value, 3.5);
  EXPECT_EQ(s1.max.value, 3.5);
  // Constant data: sd 0, no std CI.
  const std::vector<double> same(50, 2.0);
  const Summary sc = ps::summarize(same);
  EXPECT_EQ(sc.std.value, 0.0);
  EXPECT_FALSE(sc.std.lo.has_value());
  EXPECT_EQ(sc.p95.value, 2.0);
}

TEST(Statistics, EmptyThrows) {
  const std::vector<double> empty;
  EXPECT_THROW(ps::summarize(empty), Error);
  EXPECT_THROW(ps::quantile_sorted(empty, 0.5), Error);
  EXPECT_THROW(ps::fraction_wilson(0, 0), Error);
}

// n standard normal values from a stream keyed by replicate r.
std::vector<double> normal_sample(std::uint64_t r, std::size_t n) {
  RandomStream rs(20240601, StreamId::kProcedure, r);
  std::vector<double> v(n);
  for (auto& x : v) x = ps::standard_normal_quantile(rs.uniform());
  return v;
}

TEST(Statistics, MeanAndStdIntervalsCoverTheTruth) {
  // 400 runs of n = 200 standard normals. Nominal coverage 95%: a correct interval covers in
  // 368-390 of 400 runs with probability 99%, an interval twice too wide (the delta method's
  // 1/2 dropped) in about 400 and fails; the streams are fixed, the outcome deterministic.
  int mean_hits = 0, std_hits = 0;
  for (std::uint64_t r = 0; r < 400; ++r) {
    const Summary s = ps::summarize(normal_sample(r, 200));
    ASSERT_TRUE(s.mean.lo && s.mean.hi && s.std.lo && s.std.hi);
    mean_hits += *s.mean.lo <= 0.0 && 0.0 <= *s.mean.hi;
    std_hits += *s.std.lo <= 1.0 && 1.0 <= *s.std.hi;
    // The mean CI half-width is close to 1.972 / sqrt(200) = 0.139 for sd ~ 1.
    EXPECT_NEAR(*s.mean.hi - *s.mean.lo, 2.0 * 1.9719565 * s.std.value / std::sqrt(200.0), 1e-6);
  }
  EXPECT_GE(mean_hits, 368);
  EXPECT_LE(mean_hits, 390);
  EXPECT_GE(std_hits, 364);  // asymptotic interval, slightly below nominal at n = 200
  EXPECT_LE(std_hits, 390);
}

TEST(Statistics, ShareGetsTheExactBinomialInterval) {
  // 64 passes in 64: the t interval would be [1, 1]; Clopper-Pearson's lower end solves
  // p^64 = 0.025 (closed form).
  const Summary all = ps::summarize(std::vector<double>(64, 1.0));
  ASSERT_TRUE(all.mean.lo && all.mean.hi);
  EXPECT_NEAR(*all.mean.lo, std::pow(0.025, 1.0 / 64.0), 1e-12);
  EXPECT_EQ(*all.mean.hi, 1.0);
  EXPECT_NE(all.mean.note.find("Clopper-Pearson"), std::string::npos);
  const Summary none = ps::summarize(std::vector<double>(64, 0.0));
  EXPECT_EQ(*none.mean.lo, 0.0);
  EXPECT_NEAR(*none.mean.hi, 1.0 - std::pow(0.025, 1.0 / 64.0), 1e-12);
  // Coverage: 1000 draws of 64 units at a pass probability of 0.9; the exact interval covers
  // at least 95% (it is conservative), a t interval covers about 93%.
  RandomStream rs(2026, StreamId::kBootstrap, 3);
  int hits = 0;
  for (int r = 0; r < 1000; ++r) {
    std::vector<double> v(64);
    for (double& x : v) x = rs.uniform() < 0.9 ? 1.0 : 0.0;
    const Summary s = ps::summarize(v);
    hits += *s.mean.lo <= 0.9 && 0.9 <= *s.mean.hi;
  }
  EXPECT_GE(hits, 950);
  EXPECT_LE(hits, 995);
}

TEST(Statistics, QuantileIntervalCoversTheTrueNormalQuantile) {
  const double q95 = 1.6448536269514722;
  int hits = 0, missing = 0;
  for (std::uint64_t r = 0; r < 100; ++r) {
    std::vector<double> v = normal_sample(1000 + r, 200);
    std::sort(v.begin(), v.end());
    const Estimate e = ps::quantile_sorted(v, 0.95);
    if (!e.lo || !e.hi) {
      ++missing;
      continue;
    }
    EXPECT_LE(*e.lo, e.value);
    EXPECT_GE(*e.hi, e.value);
    hits += *e.lo <= q95 && q95 <= *e.hi;
  }
  EXPECT_EQ(missing, 0);  // n = 200 is enough for both ends of a p95 interval
  EXPECT_GE(hits, 90);
}

TEST(Statistics, QuantileIntervalIsTheExactBinomialOrderStatisticInterval) {
  // Independent check of the order statistics chosen for n = 200, p = 0.95 by exact binomial
  // sums: l = largest l with P(B <= l - 1) <= 0.025, u = smallest u with P(B <= u - 1) >= 0.975.
  const int n = 200;
  const double p = 0.95;
  std::vector<double> cdf(n + 1);
  double acc = 0.0;
  for (int k = 0; k <= n; ++k) {
    const double logc = std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0);
    acc += std::exp(logc + k * std::log(p) + (n - k) * std::log1p(-p));
    cdf[static_cast<std::size_t>(k)] = acc;
  }
  // Data x(i) = i (1-based) so the CI ends read off the order statistic indices directly.
  std::vector<double> v(n);
  for (int i = 0; i < n; ++i) v[static_cast<std::size_t>(i)] = i + 1;
  const Estimate e = ps::quantile_sorted(v, p);
  ASSERT_TRUE(e.lo && e.hi);
  const int l = static_cast<int>(*e.lo), u = static_cast<int>(*e.hi);
  // Coverage P(l <= B <= u - 1) >= 0.95 where B = #samples below the true quantile.
  const double coverage = cdf[static_cast<std::size_t>(u - 1)] - (l >= 1 ? cdf[static_cast<std::size_t>(l - 1)] : 0.0);
  EXPECT_GE(coverage, 0.95);
  // Each tail at most 2.5%...
  EXPECT_LE(l >= 1 ? cdf[static_cast<std::size_t>(l - 1)] : 0.0, 0.025);
  EXPECT_GE(cdf[static_cast<std::size_t>(u - 1)], 0.975);
  // ...and the ends are the tightest such order statistics: X(l + 1) would leave more than
  // 2.5% below, X(u - 1) more than 2.5% above. By hand: P(B <= 183) = 0.0238,
  // P(B <= 184) = 0.0444 -> l = 184; P(B <= 195) = 0.9736, P(B <= 196) = 0.9910 -> u = 197.
  EXPECT_GT(cdf[static_cast<std::size_t>(l)], 0.025) << "lower end X(" << l << ") is not the tightest";
  EXPECT_LT(cdf[static_cast<std::size_t>(u - 2)], 0.975) << "upper end X(" << u << ") is not the tightest";
  EXPECT_EQ(l, 184);
  EXPECT_EQ(u, 197);
  // n = 5, median: P(B = 0) = 1/32 > 2.5%, so neither end exists.
  const std::vector<double> five{1, 2, 3, 4, 5};
  const Estimate m5 = ps::quantile_sorted(five, 0.5);
  EXPECT_FALSE(m5.lo.has_value());
  EXPECT_FALSE(m5.hi.has_value());
  EXPECT_EQ(m5.value, 3.0);
}

TEST(Statistics, QuantileDefinitionEight) {
  const std::vector<double> v{1.0, 2.0, 4.0, 8.0};
  EXPECT_NEAR(ps::quantile_sorted(v, 0.0).value, 1.0, 0.0);
  EXPECT_NEAR(ps::quantile_sorted(v, 1.0).value, 8.0, 0.0);
  EXPECT_NEAR(ps::quantile_sorted(v, 0.5).value, 3.0, 1e-15);             // h = 2.5
  EXPECT_NEAR(ps::quantile_sorted(v, 0.25).value, 1.0 + 5.0 / 12.0, 1e-15);  // h = 17/12
  std::vector<double> w{8.0, 1.0, 4.0, 2.0};
  EXPECT_NEAR(ps::quantile_value(w, 0.25), 1.0 + 5.0 / 12.0, 1e-15);
}

TEST(Statistics, UpperEndOfTheP9973IntervalNeeds1365Samples) {
  // 1 - 0.9973^n >= 0.975 first at n = 1365 (0.9973^1364 = 0.02505, 0.9973^1365 = 0.02498).
  EXPECT_EQ(ps::samples_for_upper_end(0.9973), 1365u);
  EXPECT_EQ(ps::samples_for_upper_end(0.95), 72u);
  for (std::size_t n : {1364u, 1365u}) {
    std::vector<double> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<double>(i);
    const ps::Estimate e = ps::quantile_sorted(v, 0.9973);
    EXPECT_EQ(e.hi.has_value(), n == 1365u) << n;
    EXPECT_EQ(e.note.empty(), n == 1365u) << e.note;
  }
}

TEST(Statistics, DefinitionEightIsMedianUnbiasedInTheTail) {
  // 400 runs of n = 1024 standard normals: the share of runs whose p99.73 lies below the true
  // 2.78215 must be about 1/2 (band for 400 runs: 0.43-0.57). Definition 7 (h = (n - 1) p + 1,
  // between X(1021) and X(1022)) lies below in about 65% of runs: X(1022) < q when at most 2
  // of 1024 values exceed q (P = 0.48), X(1021) < q when at most 3 do (P = 0.70).
  const double q = 2.7821504537846;  // standard normal quantile of 0.9973
  EXPECT_NEAR(ps::standard_normal_quantile(0.9973), q, 1e-9);
  int below8 = 0, below7 = 0;
  for (std::uint64_t r = 0; r < 400; ++r) {
    std::vector<double> v = normal_sample(5000 + r, 1024);
    std::sort(v.begin(), v.end());
    below8 += ps::quantile_sorted(v, 0.9973).value < q;
    const double h7 = 1023.0 * 0.9973;  // 0-based
    const auto i = static_cast<std::size_t>(h7);
    below7 += v[i] + (h7 - static_cast<double>(i)) * (v[i + 1] - v[i]) < q;
  }
  std::printf("  p99.73 at n = 1024, 400 runs: below the truth %d (definition 8), %d (definition 7)\n", below8, below7);
  EXPECT_GE(below8, 172);
  EXPECT_LE(below8, 228);
  EXPECT_GT(below7, 240);  // the definition this replaced, biased low
}

TEST(Statistics, WilsonInterval) {
  // 0 of 10: lo = 0, hi = (z^2/n) / (1 + z^2/n) = 0.27753.
  const Estimate e0 = ps::fraction_wilson(0, 10);
  EXPECT_EQ(e0.value, 0.0);
  ASSERT_TRUE(e0.lo && e0.hi);
  EXPECT_EQ(*e0.lo, 0.0);
  const double zz = kZ975 * kZ975 / 10.0;
  EXPECT_NEAR(*e0.hi, zz / (1.0 + zz), 1e-14);
  EXPECT_NEAR(*e0.hi, 0.2775, 5e-5);

  // 5 of 10: symmetric about 0.5, half-width z sqrt(0.025 + z^2/400) / (1 + z^2/10).
  const Estimate e5 = ps::fraction_wilson(5, 10);
  ASSERT_TRUE(e5.lo && e5.hi);
  EXPECT_EQ(e5.value, 0.5);
  EXPECT_NEAR(*e5.lo + *e5.hi, 1.0, 1e-15);
  const double half = kZ975 * std::sqrt(0.025 + kZ975 * kZ975 / 400.0) / (1.0 + zz);
  EXPECT_NEAR(*e5.hi - 0.5, half, 1e-14);
  EXPECT_NEAR(*e5.lo, 0.2366, 1e-4);  // tabulated Wilson interval for 5/10: [0.2366, 0.7634]

  // n of n mirrors 0 of n.
  const Estimate e10 = ps::fraction_wilson(10, 10);
  ASSERT_TRUE(e10.lo && e10.hi);
  EXPECT_NEAR(*e10.hi, 1.0, 1e-15);
  EXPECT_NEAR(*e10.lo, 1.0 - *e0.hi, 1e-14);
}

}  // namespace
