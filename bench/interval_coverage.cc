// Coverage of the 95% interval of p99.73 (issue 21): not a unit test (about a minute of
// sampling), run by hand and its table quoted in the commit:
//   build/bench/poise_interval_coverage [runs]
// For plain Monte Carlo and for scrambled Sobol / LHS replicates of several sizes, `runs`
// independent runs of a chi(6) output (the magnitude of a 6-dimensional standard normal,
// whose quantiles are known in closed form) are summarized by sampling/statistics.h, and the
// share of runs whose interval holds the true p99.73 is printed with its own 95% (Wilson)
// interval, beside the share of one-sided intervals, the median bias of the point estimate
// (share of runs below the truth: 50% for a median-unbiased one) and its mean error; and, for
// the replicates, the coverage of the interval this replaced (pooled +- t x the standard error
// of each replicate's own p99.73).
#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "sampling/design.h"
#include "sampling/distribution.h"
#include "sampling/statistics.h"

namespace ps = poise::sampling;

namespace {

constexpr int kDof = 6;
constexpr double kP = 0.9973;

double chi_of(std::span<const double> u) {
  double s = 0.0;
  for (double x : u) s += ps::standard_normal_quantile(x) * ps::standard_normal_quantile(x);
  return std::sqrt(s);
}

std::string share(int k, int n) {
  const ps::Estimate e = ps::fraction_wilson(static_cast<std::size_t>(k), static_cast<std::size_t>(n));
  char buf[64];
  std::snprintf(buf, sizeof buf, "%5.1f%% [%4.1f, %5.1f]", 100 * e.value, 100 * *e.lo, 100 * *e.hi);
  return buf;
}

void run(const char* label, ps::SamplingMethod method, std::size_t m, std::size_t reps, int runs, double truth) {
  int covered = 0, one_sided = 0, below = 0, old_covered = 0;
  double error_sum = 0.0;
  const std::size_t n = m * reps;
  for (int t = 0; t < runs; ++t) {
    ps::DesignOptions o;
    o.replicate_size = reps > 1 ? m : 0;
    const ps::Design d(method, 90000 + static_cast<std::uint64_t>(t), n, kDof, o);
    std::vector<double> v(n), u(kDof);
    std::vector<std::size_t> rep(n);
    for (std::size_t i = 0; i < n; ++i) {
      d.point(i, u);
      v[i] = chi_of(u);
      rep[i] = i / m;
    }
    const ps::Summary s = reps > 1 ? ps::summarize_replicates(v, rep) : ps::summarize(v);
    const ps::Estimate& e = s.p99_73;
    one_sided += !e.hi || !e.lo;
    covered += (!e.lo || *e.lo <= truth) && (!e.hi || truth <= *e.hi) && (e.lo || e.hi);
    below += e.value < truth;
    error_sum += e.value - truth;
    if (reps > 1) {  // the replaced interval: spread of each replicate's own p99.73
      std::vector<double> q;
      for (std::size_t r = 0; r < reps; ++r) {
        std::vector<double> g(v.begin() + static_cast<long>(r * m), v.begin() + static_cast<long>((r + 1) * m));
        std::sort(g.begin(), g.end());
        q.push_back(ps::quantile_sorted(g, kP).value);
      }
      double mean = 0, ss = 0;
      for (double x : q) mean += x;
      mean /= static_cast<double>(reps);
      for (double x : q) ss += (x - mean) * (x - mean);
      const double half = boost::math::quantile(boost::math::students_t(static_cast<double>(reps - 1)), 0.975) *
                          std::sqrt(ss / static_cast<double>(reps - 1) / static_cast<double>(reps));
      old_covered += std::abs(e.value - truth) <= half;
    }
  }
  std::printf("%-34s n=%6zu  covers %s  one-sided %5.1f%%  below truth %5.1f%%  mean error %+.4f", label, n,
              share(covered, runs).c_str(), 100.0 * one_sided / runs, 100.0 * below / runs, error_sum / runs);
  if (reps > 1) std::printf("  | replaced interval covers %s", share(old_covered, runs).c_str());
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::atoi(argv[1]) : 400;
  const double truth = std::sqrt(boost::math::quantile(boost::math::chi_squared(kDof), kP));
  std::printf("p99.73 of chi(%d) = %.6f; %d runs each; covers = share of runs whose 95%% interval holds it "
              "(a one-sided interval covers when its end does)\n",
              kDof, truth, runs);
  run("monte carlo", ps::SamplingMethod::kMonteCarlo, 1024, 1, runs, truth);
  run("monte carlo", ps::SamplingMethod::kMonteCarlo, 4096, 1, runs, truth);
  run("monte carlo", ps::SamplingMethod::kMonteCarlo, 16384, 1, runs, truth);
  run("sobol 16 x 64 (issue 21's layout)", ps::SamplingMethod::kSobol, 64, 16, runs, truth);
  run("sobol 16 x 1024", ps::SamplingMethod::kSobol, 1024, 16, runs, truth);
  run("sobol 8 x 4096", ps::SamplingMethod::kSobol, 4096, 8, runs, truth);
  run("lhs 16 x 1024", ps::SamplingMethod::kLatinHypercube, 1024, 16, runs, truth);
  run("lhs 8 x 4096", ps::SamplingMethod::kLatinHypercube, 4096, 8, runs, truth);
  return 0;
}
