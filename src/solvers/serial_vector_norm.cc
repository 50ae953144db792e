#include "solvers/serial_vector_norm.h"

#include <cmath>

namespace poise::solvers {

sunrealtype weighted_rms_norm(N_Vector x, N_Vector w) {
  const sunindextype n = NV_LENGTH_S(x);
  const double* a = NV_DATA_S(x);
  const double* b = NV_DATA_S(w);
  double even = 0.0, odd = 0.0;  // two chains: half the dependent additions
  sunindextype i = 0;
  for (; i + 1 < n; i += 2) {
    const double p0 = a[i] * b[i], p1 = a[i + 1] * b[i + 1];
    even += p0 * p0, odd += p1 * p1;
  }
  if (i < n) even += (a[i] * b[i]) * (a[i] * b[i]);
  return std::sqrt((even + odd) / static_cast<double>(n));
}

void use_weighted_rms_norm(N_Vector v) { v->ops->nvwrmsnorm = weighted_rms_norm; }

}  // namespace poise::solvers
