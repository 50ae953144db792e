#include "sampling/design.h"

#include <boost/random/sobol.hpp>
#include <algorithm>
#include <numeric>

#include "core/error.h"
#include "sampling/random_stream.h"

namespace poise::sampling {

SamplingMethod parse_sampling_method(std::string_view name) {
  if (name == "monte_carlo") return SamplingMethod::kMonteCarlo;
  if (name == "lhs") return SamplingMethod::kLatinHypercube;
  if (name == "sobol") return SamplingMethod::kSobol;
  throw Error("unknown sampling method \"" + std::string(name) +
              "\"; expected \"monte_carlo\", \"lhs\" or \"sobol\"");
}

std::string to_string(SamplingMethod method) {
  switch (method) {
    case SamplingMethod::kMonteCarlo: return "monte_carlo";
    case SamplingMethod::kLatinHypercube: return "lhs";
    case SamplingMethod::kSobol: return "sobol";
  }
  return "?";
}

Design::Design(SamplingMethod method, std::uint64_t seed, std::size_t n_samples,
               std::size_t dimension)
    : method_(method), seed_(seed), n_samples_(n_samples), dimension_(dimension) {
  require(n_samples > 0, "a design needs at least one sample");
  if (method == SamplingMethod::kLatinHypercube) {
    require(n_samples <= 0xffffffffu, "Latin hypercube limited to 2^32 samples");
    lhs_permutation_.resize(dimension);
    for (std::size_t d = 0; d < dimension; ++d) {
      auto& perm = lhs_permutation_[d];
      perm.resize(n_samples);
      std::iota(perm.begin(), perm.end(), 0u);
      RandomStream rs(seed, StreamId::kLhsPermutation, d);
      for (std::size_t k = n_samples - 1; k > 0; --k) {
        // Modulo bias is below (k+1)/2^64, negligible for any feasible N.
        const auto j = static_cast<std::size_t>(rs.next_bits() % (k + 1));
        std::swap(perm[k], perm[j]);
      }
    }
  } else if (method == SamplingMethod::kSobol) {
    require(dimension <= boost::random::default_sobol_table::max_dimension,
            "Sobol design limited to " + std::to_string(boost::random::default_sobol_table::max_dimension) +
                " dimensions");
    RandomStream rs(seed, StreamId::kSobolShift, 0);
    sobol_shift_.resize(dimension);
    for (auto& s : sobol_shift_) s = rs.next_bits();
  }
}

void Design::point(std::size_t i, std::span<double> u) const {
  require(u.size() == dimension_, "design point buffer has the wrong size");
  switch (method_) {
    case SamplingMethod::kMonteCarlo: {
      RandomStream rs(seed_, StreamId::kDesign, i);
      for (auto& x : u) x = rs.uniform();
      break;
    }
    case SamplingMethod::kLatinHypercube: {
      RandomStream rs(seed_, StreamId::kLhsJitter, i);
      const double n = static_cast<double>(n_samples_);
      for (std::size_t d = 0; d < dimension_; ++d) {
        // Rounding could reach the top of the stratum (1.0 in the last one): clamp inside.
        u[d] = std::min((static_cast<double>(lhs_permutation_[d][i]) + rs.uniform()) / n,
                        1.0 - 0x1.0p-53);
      }
      break;
    }
    case SamplingMethod::kSobol: {
      if (dimension_ == 0) return;
      // One engine per thread, re-positioned to point i (Gray-code jump, O(dim*64)).
      // Boost's seed(k) positions the engine so that its next vector is point k+1; point 0
      // is the origin, which the digital shift moves off zero.
      thread_local boost::random::sobol engine(1);
      if (engine.dimension() != dimension_) engine = boost::random::sobol(dimension_);
      if (i > 0) engine.seed(static_cast<boost::uint_least64_t>(i) - 1);
      for (std::size_t d = 0; d < dimension_; ++d) {
        const std::uint64_t raw = i > 0 ? static_cast<std::uint64_t>(engine()) : 0;
        u[d] = to_open_unit(raw ^ sobol_shift_[d]);
      }
      break;
    }
  }
}

}  // namespace poise::sampling
