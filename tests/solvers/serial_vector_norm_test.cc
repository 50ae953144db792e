// The weighted RMS norm CVODE uses on Poise's serial vectors, against SUNDIALS' own.
#include "solvers/serial_vector_norm.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sundials_context.h"

namespace poise::solvers {
namespace {

using Sundials = test::SundialsContext;

TEST(WeightedRmsNorm, EqualsSundialsOwnAtEverySmallSize) {
  Sundials s;
  std::mt19937_64 gen(3);
  std::normal_distribution<double> z;
  for (sunindextype n = 1; n <= 21; ++n) {
    N_Vector x = N_VNew_Serial(n, s.ctx), w = N_VNew_Serial(n, s.ctx);
    for (sunindextype i = 0; i < n; ++i) NV_Ith_S(x, i) = z(gen), NV_Ith_S(w, i) = std::abs(z(gen)) * 1e4;
    const double theirs = N_VWrmsNorm_Serial(x, w);
    use_weighted_rms_norm(x);
    EXPECT_NEAR(N_VWrmsNorm(x, w), theirs, 1e-14 * theirs) << n;
    N_Vector clone = N_VClone(x);  // CVODE's work vectors are clones: they inherit it
    EXPECT_EQ(clone->ops->nvwrmsnorm, &weighted_rms_norm);
    N_VDestroy(clone), N_VDestroy(x), N_VDestroy(w);
  }
}

}  // namespace
}  // namespace poise::solvers
