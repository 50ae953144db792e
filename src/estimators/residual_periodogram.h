#pragma once
/// The periodogram test of the omnibus family (residual_omnibus.h): is there a period in the
/// residual, in measurement order, that no candidate effect names?
///
///   statistic  max_f |sum_t r'_t exp(-2 pi i f t)|^2 / sum_t r'_t^2, r' = r minus its mean, over
///              f = j / (8 n), j = 1 .. 8 floor((n - 1) / 2) cycles per point: the periodogram's
///              largest ordinate over the sum of squares, on a grid 8 times finer than the
///              Fourier frequencies k / n (zero padding to 8 n, one FFT), so that a period that
///              divides no record length is not split between two ordinates. On the Fourier
///              frequencies alone it is about n / 2 times Fisher's g (Fisher 1929), whose white-noise
///              tail is P(g > x) = sum_{j x < 1} (-1)^(j-1) C(m, j) (1 - j x)^(m-1); on the finer
///              grid there is no closed form, and a regression's residual is not white anyway.
///   p value    Monte Carlo: 400 draws r = (I - H) z, z ~ N(0, I), H the hat matrix of the
///              design (white draws when no design is given, e.g. AR(1) innovations), fixed
///              seed; p = (1 + #{T_sim >= T}) / 401, exact under Gaussian errors.
/// Measured: the third generator's sawtooth (period 10 of 36 rows, z = 9): p = 0.005; Fisher's g
/// on the Fourier frequencies alone: p = 0.09 (tests/third_gimbal_data/README.md).
#include "estimators/residual_omnibus.h"

#include <vector>

namespace poise::estimators {

/// The statistic above of r (in measurement order); *frequency (when given) receives where it
/// sits, in cycles per point. 0 for a constant r.
double periodogram_peak(const std::vector<double>& r, double* frequency);

/// The test on `ordered` (in.residual in measurement order), with its Monte Carlo p under
/// in.design. Not examined below 12 points or for a zero residual.
StructureTest periodogram_test(const OmnibusInput& in, const std::vector<double>& ordered);

}  // namespace poise::estimators
