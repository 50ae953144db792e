#include "estimators/residual_periodogram.h"

#include "core/format.h"

#include <algorithm>
#include <complex>
#include <numeric>
#include <unsupported/Eigen/FFT>

namespace poise::estimators {

double periodogram_peak(const std::vector<double>& r, double* frequency) {
  constexpr std::size_t kOversampling = 8;
  const std::size_t n = r.size(), padded = kOversampling * n, last = kOversampling * ((n - 1) / 2);
  const double mean = std::accumulate(r.begin(), r.end(), 0.0) / static_cast<double>(n);
  std::vector<double> x(padded, 0.0);
  double energy = 0.0;
  for (std::size_t t = 0; t < n; ++t) {
    x[t] = r[t] - mean;
    energy += x[t] * x[t];
  }
  if (!(energy > 0.0)) return 0.0;
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> spectrum;
  fft.fwd(spectrum, x);
  double best = 0.0;
  for (std::size_t j = 1; j <= last; ++j) {
    const double ordinate = std::norm(spectrum[j]);
    if (ordinate > best) {
      best = ordinate;
      if (frequency) *frequency = static_cast<double>(j) / static_cast<double>(padded);
    }
  }
  return best / energy;
}

StructureTest periodogram_test(const OmnibusInput& in, const std::vector<double>& ordered) {
  StructureTest t;
  t.name = "periodogram";
  const std::size_t n = ordered.size();
  if (n < 12) {
    t.note = "not examined: fewer than 12 points";
    return t;
  }
  double frequency = 0.0;
  t.statistic = periodogram_peak(ordered, &frequency);
  if (!(t.statistic > 0.0)) {
    t.note = "not examined: the residuals are zero";
    return t;
  }
  constexpr int kDraws = 400;
  const bool projected = in.design.rows() == static_cast<Eigen::Index>(n) && in.design.cols() > 0 && !in.ar;
  ResidualDraws draws(in, projected, 0x9e710d0u);
  std::vector<double> draw(n);
  int exceed = 0;
  for (int k = 0; k < kDraws; ++k) {
    draws.next(draw);
    exceed += periodogram_peak(draw, nullptr) >= t.statistic;
  }
  t.p_value = (1.0 + exceed) / (kDraws + 1.0);
  t.examined = true;
  t.note = fmt::format("strongest period {:.3g} points; Monte Carlo p {}", 1.0 / frequency,
                       projected ? "under the design" : "against white noise");
  return t;
}

}  // namespace poise::estimators
