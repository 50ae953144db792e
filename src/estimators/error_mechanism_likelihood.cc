#include "estimators/error_mechanism_likelihood.h"

#include <algorithm>
#include <boost/math/tools/minima.hpp>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include "core/angles.h"
#include "core/error.h"

namespace poise::estimators {
namespace {

using angles::kTwoPi;

// Which sigmas a mechanism frees, and ties: `additive` has one s_d for both components.
struct Freedom {
  bool scale, zero, along, across, tied;
};

Freedom freedom(ErrorMechanism m) {
  switch (m) {
    case ErrorMechanism::kScaleAndZero: return {true, true, false, false, false};
    case ErrorMechanism::kAdditive: return {false, false, true, true, true};
    case ErrorMechanism::kAdditiveAlongAcross: return {false, false, true, true, false};
    case ErrorMechanism::kScaleZeroAndAdditive: return {true, true, true, true, true};
  }
  return {false, false, false, false, false};
}

double normal_log_density(double x, double var) { return -0.5 * (std::log(kTwoPi * var) + x * x / var); }

std::vector<double> ranks(std::span<const double> x) {
  std::vector<std::size_t> idx(x.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return x[a] < x[b]; });
  std::vector<double> r(x.size());
  for (std::size_t i = 0; i < idx.size();) {
    std::size_t j = i;
    while (j + 1 < idx.size() && x[idx[j + 1]] == x[idx[i]]) ++j;
    const double avg = 0.5 * static_cast<double>(i + j) + 1.0;
    for (std::size_t k = i; k <= j; ++k) r[idx[k]] = avg;
    i = j + 1;
  }
  return r;
}

}  // namespace

const char* to_string(ErrorMechanism m) {
  switch (m) {
    case ErrorMechanism::kScaleAndZero: return "scale_and_zero";
    case ErrorMechanism::kAdditive: return "additive";
    case ErrorMechanism::kAdditiveAlongAcross: return "additive_along_across";
    case ErrorMechanism::kScaleZeroAndAdditive: return "scale_zero_and_additive";
  }
  return "?";
}

int parameter_count(ErrorMechanism m) {
  const Freedom f = freedom(m);
  return int(f.scale) + int(f.zero) + (f.tied ? 1 : int(f.along) + int(f.across));
}

LoadFrameError load_frame_error(const UnbalanceTestRecord& t) {
  const double d = t.angle - t.load_angle;
  return {t.torque * std::cos(d) - t.load_torque, t.torque * std::sin(d)};
}

double mechanism_log_likelihood(std::span<const UnbalanceTestRecord> tests, const MechanismSigmas& s,
                                double position_noise) {
  double ll = 0.0;
  for (const auto& t : tests) {
    if (t.positions < 4)
      throw Error("error-mechanism likelihood: test " + std::to_string(t.number) + " of " + t.table + " has " +
                  std::to_string(t.positions) + " positions (at least 4 expected)");
    const LoadFrameError e = load_frame_error(t);
    const double noise = fit_noise_variance(position_noise, t.positions);
    const double l2 = t.load_torque * t.load_torque;
    const double var_r = l2 * s.scale * s.scale + s.along * s.along + noise;
    const double var_t = l2 * s.zero * s.zero + s.across * s.across + noise;
    if (!(var_r > 0.0) || !(var_t > 0.0)) {
      throw Error("error-mechanism likelihood: zero variance (every sigma and the position noise are 0)");
    }
    ll += normal_log_density(e.along, var_r) + normal_log_density(e.across, var_t);
  }
  return ll;
}

MechanismSigmas fit_mechanism(std::span<const UnbalanceTestRecord> tests, ErrorMechanism m, double position_noise) {
  if (tests.empty()) throw Error("error-mechanism fit: no tests");
  const Freedom f = freedom(m);
  double largest = 0.0, largest_load = 0.0;
  for (const auto& t : tests) {
    const LoadFrameError e = load_frame_error(t);
    largest = std::max({largest, std::abs(e.along), std::abs(e.across)});
    largest_load = std::max(largest_load, t.load_torque);
  }
  MechanismSigmas s;
  auto ll = [&](const MechanismSigmas& x) { return mechanism_log_likelihood(tests, x, position_noise); };
  // One coordinate: maximise over sigma in [0, hi] with the others held.
  auto search = [&](auto set, double hi) {
    const auto r = boost::math::tools::brent_find_minima(
        [&](double v) {
          MechanismSigmas x = s;
          set(x, v);
          return -ll(x);
        },
        0.0, hi, 40);
    MechanismSigmas x = s;
    set(x, r.first);
    // Brent does not evaluate the end point: the boundary sigma = 0 wins when it is better.
    MechanismSigmas z = s;
    set(z, 0.0);
    s = ll(z) >= ll(x) ? z : x;
  };
  const double hi_rel = largest_load > 0 ? 10.0 * largest / largest_load : 1.0;
  double previous = -std::numeric_limits<double>::infinity();
  for (int sweep = 0; sweep < 200; ++sweep) {
    if (f.scale) search([](MechanismSigmas& x, double v) { x.scale = v; }, hi_rel);
    if (f.zero) search([](MechanismSigmas& x, double v) { x.zero = v; }, hi_rel);
    if (f.tied) {
      search([](MechanismSigmas& x, double v) { x.along = x.across = v; }, 10.0 * largest);
    } else {
      if (f.along) search([](MechanismSigmas& x, double v) { x.along = v; }, 10.0 * largest);
      if (f.across) search([](MechanismSigmas& x, double v) { x.across = v; }, 10.0 * largest);
    }
    const double now = ll(s);
    if (now - previous < 1e-10) break;
    previous = now;
  }
  return s;
}

double pearson(std::span<const double> x, std::span<const double> y) {
  const double n = static_cast<double>(x.size());
  const double mx = std::accumulate(x.begin(), x.end(), 0.0) / n, my = std::accumulate(y.begin(), y.end(), 0.0) / n;
  double sxy = 0, sxx = 0, syy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
    syy += (y[i] - my) * (y[i] - my);
  }
  return sxx > 0 && syy > 0 ? sxy / std::sqrt(sxx * syy) : 0.0;
}

double spearman(std::span<const double> x, std::span<const double> y) {
  const std::vector<double> rx = ranks(x), ry = ranks(y);
  return pearson(rx, ry);
}

PredictiveCheck predictive_check(std::span<const UnbalanceTestRecord> tests, const MechanismSigmas& s,
                                 double position_noise, int draws, std::uint64_t seed) {
  const std::size_t n = tests.size();
  std::vector<double> load(n), dmt(n), db(n);
  auto statistics = [&](double& st, double& sa, double& p) {
    std::vector<double> adm(n), adb(n);
    for (std::size_t i = 0; i < n; ++i) {
      adm[i] = std::abs(dmt[i]);
      adb[i] = std::abs(db[i]);
    }
    st = spearman(load, adm);
    sa = spearman(load, adb);
    p = pearson(dmt, db);
  };
  for (std::size_t i = 0; i < n; ++i) {
    load[i] = tests[i].load_torque;
    dmt[i] = tests[i].torque - tests[i].load_torque;
    db[i] = std::remainder(tests[i].angle - tests[i].load_angle, kTwoPi);
  }
  PredictiveCheck c;
  statistics(c.spearman_torque, c.spearman_angle, c.pearson_torque_angle);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> z(0.0, 1.0);
  int below_t = 0, below_a = 0, beyond_p = 0;
  for (int k = 0; k < draws; ++k) {
    for (std::size_t i = 0; i < n; ++i) {
      const double L = tests[i].load_torque;
      const double noise = std::sqrt(fit_noise_variance(position_noise, tests[i].positions));
      // The exact vector: (1 + k) R(z) U_load + d + e, in the load's frame.
      const double kk = s.scale * z(rng), zz = s.zero * z(rng);
      const double x = L * (1.0 + kk) * std::cos(zz) + s.along * z(rng) + noise * z(rng);
      const double y = L * (1.0 + kk) * std::sin(zz) + s.across * z(rng) + noise * z(rng);
      dmt[i] = std::hypot(x, y) - L;
      db[i] = std::atan2(y, x);
    }
    double st = 0, sa = 0, p = 0;
    statistics(st, sa, p);
    below_t += st <= c.spearman_torque + 1e-12;
    below_a += sa <= c.spearman_angle + 1e-12;
    beyond_p += std::abs(p) >= std::abs(c.pearson_torque_angle) - 1e-12;
  }
  c.p_spearman_torque = static_cast<double>(below_t) / draws;
  c.p_spearman_angle = static_cast<double>(below_a) / draws;
  c.p_pearson = static_cast<double>(beyond_p) / draws;
  return c;
}

}  // namespace poise::estimators
