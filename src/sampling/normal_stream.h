#pragma once
/// Standard normal variates from a counter-based RandomStream by Marsaglia's polar method
/// (no trigonometry), for noise inside a sample's procedure: deterministic for a given
/// (seed, stream, index), so any sample can be replayed.
#include <cmath>

#include "sampling/random_stream.h"

namespace poise::sampling {

class NormalStream {
 public:
  explicit NormalStream(RandomStream* rs) : rs_(rs) {}

  double next() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double v1, v2, s;
    do {
      v1 = 2.0 * rs_->uniform() - 1.0;
      v2 = 2.0 * rs_->uniform() - 1.0;
      s = v1 * v1 + v2 * v2;
    } while (s >= 1.0 || s == 0.0);
    const double f = std::sqrt(-2.0 * std::log(s) / s);
    spare_ = v2 * f;
    has_spare_ = true;
    return v1 * f;
  }

 private:
  RandomStream* rs_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace poise::sampling
