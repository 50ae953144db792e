#pragma once
/// Sampling designs: the unit-hypercube point of sample i, a pure function of
/// (method, seed, sample count, dimension, i), so any sample can be replayed alone.
///   monte_carlo : independent uniforms from Philox keyed by (seed, i).
///   lhs         : Latin hypercube; per dimension a random permutation of the N strata
///                 (Fisher-Yates keyed by (seed, dimension)) and a Philox jitter in the stratum.
///   sobol       : Boost.Random's Sobol sequence (Joe-Kuo direction numbers), point i
///                 (point 0 is the origin), randomized by a digital shift per dimension
///                 drawn from the seed, so seeds give independent replicas and every
///                 elementary interval of a 2^m-point prefix keeps exactly one point.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace poise::sampling {

enum class SamplingMethod { kMonteCarlo, kLatinHypercube, kSobol };

SamplingMethod parse_sampling_method(std::string_view name);  // "monte_carlo", "lhs", "sobol"
std::string to_string(SamplingMethod method);

class Design {
 public:
  Design(SamplingMethod method, std::uint64_t seed, std::size_t n_samples, std::size_t dimension);

  /// Fills u (size dimension()) with the design point of sample i, each in (0, 1).
  /// Thread-safe.
  void point(std::size_t i, std::span<double> u) const;

  std::size_t dimension() const { return dimension_; }
  std::size_t size() const { return n_samples_; }
  SamplingMethod method() const { return method_; }

 private:
  SamplingMethod method_;
  std::uint64_t seed_;
  std::size_t n_samples_;
  std::size_t dimension_;
  std::vector<std::vector<std::uint32_t>> lhs_permutation_;  // [dimension][sample]
  std::vector<std::uint64_t> sobol_shift_;                   // [dimension]
};

}  // namespace poise::sampling
