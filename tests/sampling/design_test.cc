// Tests of the sampling designs (src/sampling/design.h): determinism and order
// independence of point(i), range, Latin hypercube stratification, Sobol net property.
#include "sampling/design.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "core/error.h"

namespace {

using poise::Error;
using poise::sampling::Design;
using poise::sampling::SamplingMethod;
namespace ps = poise::sampling;

const SamplingMethod kAll[] = {SamplingMethod::kMonteCarlo, SamplingMethod::kLatinHypercube,
                               SamplingMethod::kSobol};

// All points of a design, row-major [i * dim + d], computed for the given order of i.
std::vector<double> points(const Design& des, const std::vector<std::size_t>& order) {
  const std::size_t dim = des.dimension();
  std::vector<double> out(des.size() * dim);
  for (std::size_t i : order) des.point(i, std::span<double>(out.data() + i * dim, dim));
  return out;
}

std::vector<std::size_t> forward(std::size_t n) {
  std::vector<std::size_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = i;
  return v;
}

TEST(Design, PointsAreDeterministicAndOrderIndependent) {
  const std::size_t n = 1000, dim = 5;
  for (SamplingMethod m : kAll) {
    SCOPED_TRACE(ps::to_string(m));
    const Design des(m, 12345, n, dim);
    const std::vector<double> fwd = points(des, forward(n));

    std::vector<std::size_t> rev = forward(n);
    std::reverse(rev.begin(), rev.end());
    EXPECT_EQ(points(des, rev), fwd);

    // A scattered order with repeats of the same index back to back.
    std::vector<std::size_t> scattered;
    for (std::size_t k = 0; k < n; ++k) {
      scattered.push_back((k * 617) % n);
      scattered.push_back((k * 617) % n);
    }
    EXPECT_EQ(points(des, scattered), fwd);

    // Two threads taking interleaved indices (odd / even), writing disjoint rows.
    std::vector<double> par(n * dim);
    auto work = [&](std::size_t first) {
      for (std::size_t i = first; i < n; i += 2) des.point(i, std::span<double>(par.data() + i * dim, dim));
    };
    std::thread t0(work, 0), t1(work, 1);
    t0.join();
    t1.join();
    EXPECT_EQ(par, fwd);

    // A second design object with the same parameters gives the same points.
    const Design again(m, 12345, n, dim);
    EXPECT_EQ(points(again, rev), fwd);
  }
}

TEST(Design, InterleavingDesignsOfOtherDimensionsDoesNotDisturbPoints) {
  // Sobol keeps a per-thread engine; another design in between (other dimension, other seed)
  // must not change a point.
  for (SamplingMethod m : kAll) {
    SCOPED_TRACE(ps::to_string(m));
    const Design a(m, 1, 64, 3), b(m, 2, 64, 7), c(m, 3, 64, 3);
    const std::vector<double> pa = points(a, forward(64));
    std::vector<double> u3(3), u7(7);
    for (std::size_t i = 0; i < 64; ++i) {
      b.point(63 - i, u7);
      c.point(i, u3);
      a.point(i, u3);
      for (std::size_t d = 0; d < 3; ++d) EXPECT_EQ(u3[d], pa[i * 3 + d]);
    }
  }
}

TEST(Design, ValuesInOpenUnitInterval) {
  for (SamplingMethod m : kAll) {
    SCOPED_TRACE(ps::to_string(m));
    const Design des(m, 99, 4096, 6);
    for (double x : points(des, forward(des.size()))) {
      ASSERT_GT(x, 0.0);
      ASSERT_LT(x, 1.0);
    }
  }
}

TEST(Design, LatinHypercubeStrataArePermutations) {
  for (std::size_t n : {1u, 2u, 7u, 1000u}) {
    const std::size_t dim = 4;
    const Design des(SamplingMethod::kLatinHypercube, 777, n, dim);
    const std::vector<double> p = points(des, forward(n));
    std::vector<std::vector<std::size_t>> strata(dim);
    for (std::size_t d = 0; d < dim; ++d) {
      std::vector<std::size_t> s(n);
      for (std::size_t i = 0; i < n; ++i) s[i] = static_cast<std::size_t>(std::floor(p[i * dim + d] * static_cast<double>(n)));
      strata[d] = s;
      std::sort(s.begin(), s.end());
      EXPECT_EQ(s, forward(n)) << "n = " << n << ", dimension " << d;
    }
    if (n == 1000) {
      // Dimensions use different permutations (identical ones have odds 1/1000!).
      for (std::size_t d = 1; d < dim; ++d) EXPECT_NE(strata[d], strata[0]);
      // Not the identity permutation either.
      EXPECT_NE(strata[0], forward(n));
    }
  }
}

TEST(Design, LatinHypercubeSeedsDiffer) {
  const Design a(SamplingMethod::kLatinHypercube, 1, 100, 2), b(SamplingMethod::kLatinHypercube, 2, 100, 2);
  EXPECT_NE(points(a, forward(100)), points(b, forward(100)));
}

TEST(Design, SobolOnePointPerElementaryInterval) {
  // The first 2^m points of a (digitally shifted) Sobol sequence put exactly one point in
  // each interval [k/2^m, (k+1)/2^m) of every one-dimensional projection.
  const std::size_t n = 1024, dim = 3;
  for (std::uint64_t seed : {1ull, 2ull, 31337ull}) {
    const Design des(SamplingMethod::kSobol, seed, n, dim);
    const std::vector<double> p = points(des, forward(n));
    for (std::size_t d = 0; d < dim; ++d) {
      std::vector<int> count(n, 0);
      for (std::size_t i = 0; i < n; ++i) {
        ++count[static_cast<std::size_t>(std::floor(p[i * dim + d] * static_cast<double>(n)))];
      }
      const auto empty = std::count(count.begin(), count.end(), 0);
      const auto max = *std::max_element(count.begin(), count.end());
      EXPECT_EQ(empty, 0) << "seed " << seed << ", dimension " << d;
      EXPECT_EQ(max, 1) << "seed " << seed << ", dimension " << d;
    }
  }
}

TEST(Design, SobolSeedsGiveDifferentPoints) {
  const std::size_t n = 256, dim = 3;
  const std::vector<double> a = points(Design(SamplingMethod::kSobol, 1, n, dim), forward(n));
  const std::vector<double> b = points(Design(SamplingMethod::kSobol, 2, n, dim), forward(n));
  std::size_t same = 0;
  for (std::size_t k = 0; k < a.size(); ++k) same += a[k] == b[k];
  EXPECT_EQ(same, 0u);
}

TEST(Design, SobolIsBetterThanRandomForASmoothIntegral) {
  // int_[0,1]^3 (x1 x2 x3) = 1/8. Plain MC with 1024 points has standard error
  // sqrt(1/27 - 1/64) / 32 = 4.6e-3; shifted Sobol errs ~1e-4. Require the RMS error over
  // 8 seeds to be below 1e-3.
  const std::size_t n = 1024, dim = 3;
  double sq = 0.0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const std::vector<double> p = points(Design(SamplingMethod::kSobol, seed, n, dim), forward(n));
    double s = 0.0;
    for (std::size_t i = 0; i < n; ++i) s += p[i * 3] * p[i * 3 + 1] * p[i * 3 + 2];
    const double err = s / static_cast<double>(n) - 0.125;
    sq += err * err;
  }
  EXPECT_LT(std::sqrt(sq / 8.0), 1e-3);
}

TEST(Design, MonteCarloMean) {
  const std::size_t n = 100000;
  const Design des(SamplingMethod::kMonteCarlo, 2718, n, 1);
  double s = 0.0;
  double u[1];
  for (std::size_t i = 0; i < n; ++i) {
    des.point(i, u);
    s += u[0];
  }
  // Standard error 0.289 / sqrt(1e5) = 0.00091; 0.005 is 5.5 standard errors.
  EXPECT_NEAR(s / static_cast<double>(n), 0.5, 0.005);
}

TEST(Design, ParseAndErrors) {
  EXPECT_EQ(ps::parse_sampling_method("monte_carlo"), SamplingMethod::kMonteCarlo);
  EXPECT_EQ(ps::parse_sampling_method("lhs"), SamplingMethod::kLatinHypercube);
  EXPECT_EQ(ps::parse_sampling_method("sobol"), SamplingMethod::kSobol);
  for (SamplingMethod m : kAll) EXPECT_EQ(ps::parse_sampling_method(ps::to_string(m)), m);
  for (const char* bad : {"random", "Sobol", "", "latin_hypercube"}) {
    try {
      ps::parse_sampling_method(bad);
      ADD_FAILURE() << "accepted \"" << bad << "\"";
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("unknown sampling method"), std::string::npos) << msg;
      for (const char* name : {"\"monte_carlo\"", "\"lhs\"", "\"sobol\""}) {
        EXPECT_NE(msg.find(name), std::string::npos) << msg;
      }
    }
  }
  EXPECT_THROW(Design(SamplingMethod::kMonteCarlo, 1, 0, 3), Error);
  EXPECT_THROW(Design(SamplingMethod::kSobol, 1, 10, 100000), Error);
  const Design des(SamplingMethod::kMonteCarlo, 1, 10, 3);
  std::vector<double> wrong(2);
  EXPECT_THROW(des.point(0, wrong), Error);
}

}  // namespace
