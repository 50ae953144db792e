// Tests of the tolerance distributions (src/sampling/distribution.h). Moments are checked
// by integrating the quantile function over a deterministic midpoint grid of u,
//   E[g(X)] = int_0^1 g(Q(u)) du  ~  (1/N) sum_k g(Q((k + 1/2) / N)),
// against Distribution::mean()/stddev() and against closed forms computed here.
#include "sampling/distribution.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/error.h"

namespace {

using poise::Error;
using poise::sampling::Distribution;
using poise::sampling::DistributionKind;
using poise::sampling::ToleranceConvention;
namespace ps = poise::sampling;

constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kGrid = 200000;

struct Moments {
  double mean, sd, kurtosis, min, max;
};

template <typename Q>
Moments grid_moments(Q&& q) {
  std::vector<double> x(kGrid);
  double sum = 0.0;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t k = 0; k < kGrid; ++k) {
    const double u = (static_cast<double>(k) + 0.5) / static_cast<double>(kGrid);
    x[k] = q(u);
    sum += x[k];
    lo = std::min(lo, x[k]);
    hi = std::max(hi, x[k]);
  }
  const double mean = sum / static_cast<double>(kGrid);
  double m2 = 0.0, m4 = 0.0;
  for (double v : x) {
    const double d2 = (v - mean) * (v - mean);
    m2 += d2;
    m4 += d2 * d2;
  }
  m2 /= static_cast<double>(kGrid);
  m4 /= static_cast<double>(kGrid);
  return {mean, std::sqrt(m2), m4 / (m2 * m2), lo, hi};
}

// Standard normal pdf and cdf from <cmath> only (independent of the code under test).
double phi(double x) { return std::exp(-0.5 * x * x) / std::sqrt(2.0 * kPi); }
double Phi(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

double sigmas(ToleranceConvention c) {
  switch (c) {
    case ToleranceConvention::kOneSigma: return 1.0;
    case ToleranceConvention::kTwoSigma: return 2.0;
    case ToleranceConvention::kThreeSigma: return 3.0;
    default: return 0.0;
  }
}

// Standard normal truncated symmetrically at +-k: variance and kurtosis. With
// I_n = int_{-k}^{k} x^n phi: I_0 = Z = 2 Phi(k) - 1, I_2 = Z - 2 k phi(k),
// I_4 = 3 I_2 - 2 k^3 phi(k).
double truncated_sd_factor(double k) { return std::sqrt(1.0 - 2.0 * k * phi(k) / (2.0 * Phi(k) - 1.0)); }
double truncated_kurtosis(double k) {
  const double z = 2.0 * Phi(k) - 1.0;
  const double i2 = z - 2.0 * k * phi(k);
  const double i4 = 3.0 * i2 - 2.0 * k * k * k * phi(k);
  return (i4 / z) / ((i2 / z) * (i2 / z));
}

struct Case {
  DistributionKind kind;
  ToleranceConvention conv;
  double sd;          // closed-form standard deviation for nominal 10, tolerance t
  double half_width;  // closed-form support half-width (inf for normal)
  double kurtosis;    // closed-form kurtosis
  double sd_tol;      // relative tolerance of the grid integration on sd
  double kurt_tol;    // absolute tolerance on the kurtosis
};

constexpr double kNominal = 10.0;
constexpr double kTol = 0.004;

std::vector<Case> all_cases() {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<Case> cases;
  const ToleranceConvention sigma_convs[] = {ToleranceConvention::kOneSigma, ToleranceConvention::kTwoSigma,
                                             ToleranceConvention::kThreeSigma};
  // Uniform: bounds t -> a = t, sd = t/sqrt3; k sigma -> sd = t/k, a = sqrt3 t/k.
  // The midpoint rule is exact for the mean and off by 1/(3N^2) relative in the variance.
  cases.push_back({DistributionKind::kUniform, ToleranceConvention::kBounds, kTol / std::sqrt(3.0), kTol, 1.8,
                   1e-9, 1e-8});
  for (auto c : sigma_convs) {
    const double k = sigmas(c);
    cases.push_back({DistributionKind::kUniform, c, kTol / k, std::sqrt(3.0) * kTol / k, 1.8, 1e-9, 1e-8});
  }
  // Arcsine: bounds a -> sd = a/sqrt2; kurtosis 1.5. The integrand is smooth and periodic in
  // u, so the midpoint rule converges very fast.
  cases.push_back({DistributionKind::kArcsine, ToleranceConvention::kBounds, kTol / std::sqrt(2.0), kTol, 1.5,
                   1e-9, 1e-8});
  for (auto c : sigma_convs) {
    const double k = sigmas(c);
    cases.push_back({DistributionKind::kArcsine, c, kTol / k, std::sqrt(2.0) * kTol / k, 1.5, 1e-9, 1e-8});
  }
  // Normal: sd = t/k. The grid misses the tails beyond u = 1/(2N) (|z| > 4.56), which costs
  // 3.3e-6 relative in the sd and 2.8e-4 in the kurtosis; tolerances 2e-5 and 1.5e-3.
  for (auto c : sigma_convs) {
    cases.push_back({DistributionKind::kNormal, c, kTol / sigmas(c), inf, 3.0, 2e-5, 1.5e-3});
  }
  // Truncated normal cut at +-t with sigma s = t/k.
  for (auto c : sigma_convs) {
    const double k = sigmas(c);
    cases.push_back({DistributionKind::kTruncatedNormal, c, kTol / k * truncated_sd_factor(k), kTol,
                     truncated_kurtosis(k), 1e-7, 1e-5});
  }
  return cases;
}

std::string name_of(const Case& c) { return ps::to_string(c.kind) + "/" + ps::to_string(c.conv); }

TEST(Distribution, GridMomentsMatchClosedFormsAndAccessors) {
  for (const Case& c : all_cases()) {
    SCOPED_TRACE(name_of(c));
    const Distribution d(c.kind, kNominal, kTol, c.conv);
    // Accessor against the closed form (exact formulas, double rounding only).
    EXPECT_NEAR(d.stddev(), c.sd, c.sd * 1e-13);
    EXPECT_EQ(d.mean(), kNominal);
    const Moments m = grid_moments([&](double u) { return d.quantile(u); });
    // Symmetric distributions: the midpoint grid is symmetric, so the mean is exact up to
    // summation rounding (2e5 terms of size 10: < 1e-10).
    EXPECT_NEAR(m.mean, d.mean(), 1e-10);
    EXPECT_NEAR(m.sd, d.stddev(), c.sd * c.sd_tol);
    EXPECT_NEAR(m.sd, c.sd, c.sd * c.sd_tol);
    EXPECT_NEAR(m.kurtosis, c.kurtosis, c.kurt_tol);
    // Support.
    EXPECT_EQ(d.lower(), kNominal - c.half_width);
    EXPECT_EQ(d.upper(), kNominal + c.half_width);
    EXPECT_GE(m.min, d.lower());
    EXPECT_LE(m.max, d.upper());
    if (std::isfinite(c.half_width)) {
      // The extreme grid points (u = 1/(2N) from the ends) come within 1e-3 of the half-width
      // of the support ends (worst case: truncated normal at 3 sigma, 1.9e-4).
      EXPECT_NEAR(m.max, d.upper(), c.half_width * 1e-3);
      EXPECT_NEAR(m.min, d.lower(), c.half_width * 1e-3);
    }
  }
}

TEST(Distribution, SpecificClosedForms) {
  // The closed forms named in the brief, with t = 0.004.
  const double t = kTol;
  EXPECT_NEAR(Distribution(DistributionKind::kUniform, 0, t, ToleranceConvention::kBounds).stddev(),
              t / std::sqrt(3.0), 1e-18);
  EXPECT_NEAR(Distribution(DistributionKind::kUniform, 0, t, ToleranceConvention::kThreeSigma).stddev(), t / 3.0,
              1e-18);
  EXPECT_NEAR(Distribution(DistributionKind::kArcsine, 0, t, ToleranceConvention::kBounds).stddev(),
              t / std::sqrt(2.0), 1e-18);
  EXPECT_NEAR(Distribution(DistributionKind::kNormal, 0, t, ToleranceConvention::kThreeSigma).stddev(), t / 3.0,
              1e-18);
  // Truncated normal, 2 sigma cut at +-t: s = t/2, sd = s sqrt(1 - 2 k phi(k) / (2 Phi(k) - 1)).
  // Numerically: phi(2) = 0.05399097, 2 Phi(2) - 1 = 0.9544997 -> factor 0.8796257.
  const double s = t / 2.0;
  const double expected = s * std::sqrt(1.0 - 2.0 * 2.0 * phi(2.0) / (2.0 * Phi(2.0) - 1.0));
  EXPECT_NEAR(expected / s, 0.8796257, 1e-6);
  EXPECT_NEAR(Distribution(DistributionKind::kTruncatedNormal, 0, t, ToleranceConvention::kTwoSigma).stddev(),
              expected, expected * 1e-13);
}

TEST(Distribution, QuantileIsMonotoneAndCentred) {
  for (const Case& c : all_cases()) {
    SCOPED_TRACE(name_of(c));
    const Distribution d(c.kind, kNominal, kTol, c.conv);
    EXPECT_NEAR(d.quantile(0.5), kNominal, 1e-15);
    double prev = -std::numeric_limits<double>::infinity();
    for (int k = 1; k < 1000; ++k) {
      const double u = k / 1000.0;
      const double x = d.quantile(u);
      EXPECT_GT(x, prev) << "u = " << u;
      // Symmetry about the nominal: Q(u) - m = m - Q(1 - u), to rounding of the nominal 10.
      EXPECT_NEAR(x - kNominal, kNominal - d.quantile(1.0 - u), 1e-14);
      prev = x;
    }
  }
}

TEST(Distribution, NormalQuantileKnownValues) {
  // Tabulated standard normal quantiles (15+ digits).
  EXPECT_NEAR(ps::standard_normal_quantile(0.975), 1.959963984540054, 1e-14);
  EXPECT_NEAR(ps::standard_normal_quantile(0.95), 1.6448536269514722, 1e-14);
  EXPECT_NEAR(ps::standard_normal_quantile(0.9986501019683699), 3.0, 1e-12);  // Phi(3)
  EXPECT_NEAR(ps::standard_normal_quantile(1e-10), -6.361340902404056, 1e-12);
  EXPECT_NEAR(ps::standard_normal_cdf(1.959963984540054), 0.975, 1e-15);
  EXPECT_NEAR(ps::standard_normal_cdf(-3.0), 0.0013498980316300946, 1e-17);
  for (double u : {1e-12, 1e-6, 0.01, 0.3, 0.5, 0.77, 0.999999}) {
    EXPECT_NEAR(ps::standard_normal_cdf(ps::standard_normal_quantile(u)), u, u * 1e-12);
  }
  // Through Distribution: normal 3 sigma, quantile(0.975) = m + 1.96 t/3.
  const Distribution d(DistributionKind::kNormal, 1.0, 0.3, ToleranceConvention::kThreeSigma);
  EXPECT_NEAR(d.quantile(0.975), 1.0 + 0.1 * 1.959963984540054, 1e-14);
}

TEST(Distribution, TruncatedNormalQuantileEqualsConditionedNormal) {
  // Q(u) of N(0, s^2) conditioned on |X| <= t: Phi(Q/s) = Phi(-k) + u (1 - 2 Phi(-k)).
  const Distribution d(DistributionKind::kTruncatedNormal, 0.0, 0.003, ToleranceConvention::kTwoSigma);
  const double s = 0.0015;
  for (double u : {0.001, 0.1, 0.4, 0.5, 0.8, 0.999}) {
    const double x = d.quantile(u);
    EXPECT_NEAR(Phi(x / s), Phi(-2.0) + u * (1.0 - 2.0 * Phi(-2.0)), 1e-13) << u;
  }
}

TEST(Distribution, MagnitudeQuantile) {
  // Folded normal: E|X| = sigma sqrt(2/pi), sd = sigma sqrt(1 - 2/pi). Grid tail error as above.
  const Distribution n(DistributionKind::kNormal, 5.0, 0.006, ToleranceConvention::kThreeSigma);
  const double sigma = 0.002;
  const Moments fn = grid_moments([&](double u) { return n.magnitude_quantile(u); });
  EXPECT_NEAR(fn.mean, sigma * std::sqrt(2.0 / kPi), sigma * 1e-5);
  EXPECT_NEAR(fn.sd, sigma * std::sqrt(1.0 - 2.0 / kPi), sigma * 1e-4);
  EXPECT_GE(fn.min, 0.0);

  // Folded U(-a, a) is U(0, a): magnitude_quantile(u) = a u exactly (to rounding).
  const double a = 0.0025;
  const Distribution uni(DistributionKind::kUniform, 7.0, a, ToleranceConvention::kBounds);
  for (int k = 0; k <= 100; ++k) {
    const double u = (k + 0.5) / 101.0;
    EXPECT_NEAR(uni.magnitude_quantile(u), a * u, a * 1e-15) << u;
  }
  const Moments fu = grid_moments([&](double u) { return uni.magnitude_quantile(u); });
  EXPECT_NEAR(fu.mean, a / 2.0, a * 1e-12);
  EXPECT_NEAR(fu.sd, a / std::sqrt(12.0), a * 1e-9);

  // Folded arcsine a sin(pi (u-1/2)): |X| has quantile a sin(pi u / 2), mean 2a/pi.
  const Distribution arc(DistributionKind::kArcsine, 0.0, a, ToleranceConvention::kBounds);
  const Moments fa = grid_moments([&](double u) { return arc.magnitude_quantile(u); });
  EXPECT_NEAR(fa.mean, 2.0 * a / kPi, a * 1e-9);
  EXPECT_NEAR(arc.magnitude_quantile(0.5), a * std::sin(kPi / 4.0), a * 1e-15);

  // Fixed: magnitude of the declared value.
  const Distribution fx(DistributionKind::kFixed, 1.0, 0.25, ToleranceConvention::kBounds);
  EXPECT_EQ(fx.magnitude_quantile(0.3), 0.25);
}

TEST(Distribution, Fixed) {
  const Distribution d(DistributionKind::kFixed, 2.0, 0.5, ToleranceConvention::kThreeSigma);
  EXPECT_EQ(d.quantile(0.01), 2.5);
  EXPECT_EQ(d.quantile(0.99), 2.5);
  EXPECT_EQ(d.mean(), 2.5);
  EXPECT_EQ(d.stddev(), 0.0);
  EXPECT_EQ(d.lower(), 2.5);
  EXPECT_EQ(d.upper(), 2.5);
}

TEST(Distribution, ZeroToleranceIsDegenerate) {
  for (auto kind : {DistributionKind::kNormal, DistributionKind::kUniform, DistributionKind::kArcsine,
                    DistributionKind::kTruncatedNormal}) {
    const Distribution d(kind, 3.0, 0.0, ToleranceConvention::kThreeSigma);
    SCOPED_TRACE(ps::to_string(kind));
    EXPECT_EQ(d.quantile(0.2), 3.0);
    EXPECT_EQ(d.stddev(), 0.0);
    EXPECT_EQ(d.lower(), 3.0);
    EXPECT_EQ(d.upper(), 3.0);
  }
}

std::string error_message(DistributionKind kind, double tol, ToleranceConvention conv) {
  try {
    Distribution d(kind, 0.0, tol, conv);
  } catch (const Error& e) {
    return e.what();
  }
  return "<no throw>";
}

TEST(Distribution, Errors) {
  const std::string normal_bounds =
      error_message(DistributionKind::kNormal, 0.004, ToleranceConvention::kBounds);
  EXPECT_NE(normal_bounds.find("no bounds"), std::string::npos) << normal_bounds;

  const std::string tn_bounds =
      error_message(DistributionKind::kTruncatedNormal, 0.004, ToleranceConvention::kBounds);
  EXPECT_NE(tn_bounds, "<no throw>");
  EXPECT_NE(tn_bounds.find("truncated normal"), std::string::npos) << tn_bounds;

  for (auto kind : {DistributionKind::kNormal, DistributionKind::kUniform, DistributionKind::kArcsine,
                    DistributionKind::kTruncatedNormal, DistributionKind::kFixed}) {
    const std::string neg = error_message(kind, -0.001, ToleranceConvention::kThreeSigma);
    EXPECT_NE(neg.find("negative"), std::string::npos) << ps::to_string(kind) << ": " << neg;
  }
  EXPECT_THROW(Distribution(DistributionKind::kUniform, std::nan(""), 1.0, ToleranceConvention::kBounds), Error);
  EXPECT_THROW(Distribution(DistributionKind::kUniform, 0.0, std::numeric_limits<double>::infinity(),
                            ToleranceConvention::kBounds),
               Error);
}

TEST(Distribution, ParseNames) {
  EXPECT_EQ(ps::parse_distribution_kind("normal"), DistributionKind::kNormal);
  EXPECT_EQ(ps::parse_distribution_kind("uniform"), DistributionKind::kUniform);
  EXPECT_EQ(ps::parse_distribution_kind("arcsine"), DistributionKind::kArcsine);
  EXPECT_EQ(ps::parse_distribution_kind("truncated_normal"), DistributionKind::kTruncatedNormal);
  EXPECT_EQ(ps::parse_distribution_kind("fixed"), DistributionKind::kFixed);
  for (auto kind : {DistributionKind::kNormal, DistributionKind::kUniform, DistributionKind::kArcsine,
                    DistributionKind::kTruncatedNormal, DistributionKind::kFixed}) {
    EXPECT_EQ(ps::parse_distribution_kind(ps::to_string(kind)), kind);
  }
  try {
    ps::parse_distribution_kind("gaussian");
    ADD_FAILURE() << "gaussian accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("\"gaussian\""), std::string::npos) << msg;
    for (const char* name : {"\"normal\"", "\"uniform\"", "\"arcsine\"", "\"truncated_normal\"", "\"fixed\""}) {
      EXPECT_NE(msg.find(name), std::string::npos) << msg << " lacks " << name;
    }
  }
  EXPECT_EQ(ps::parse_convention("bounds"), ToleranceConvention::kBounds);
  EXPECT_EQ(ps::parse_convention("1sigma"), ToleranceConvention::kOneSigma);
  EXPECT_EQ(ps::parse_convention("2sigma"), ToleranceConvention::kTwoSigma);
  EXPECT_EQ(ps::parse_convention("3sigma"), ToleranceConvention::kThreeSigma);
  try {
    ps::parse_convention("6sigma");
    ADD_FAILURE() << "6sigma accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    for (const char* name : {"\"bounds\"", "\"1sigma\"", "\"2sigma\"", "\"3sigma\""}) {
      EXPECT_NE(msg.find(name), std::string::npos) << msg << " lacks " << name;
    }
  }
}

TEST(Distribution, Describe) {
  const Distribution d(DistributionKind::kNormal, 0.0, 0.003e-3, ToleranceConvention::kThreeSigma);
  const std::string s = d.describe(1e-3, "mm");
  EXPECT_NE(s.find("normal"), std::string::npos) << s;
  EXPECT_NE(s.find("3sigma"), std::string::npos) << s;
  EXPECT_NE(s.find("sigma = 0.001 mm"), std::string::npos) << s;
}

}  // namespace
