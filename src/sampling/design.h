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
///
/// Options (DesignOptions):
///   replicate_size M : randomized replicates for honest confidence intervals with lhs and
///                 sobol (whose points are not independent): sample i belongs to replicate
///                 r = i / M, point j = i % M of an independent design of M points with
///                 seed_r drawn from (seed, r). For sobol a replicate is scrambled by a
///                 random linear matrix scramble plus digital shift (Matousek 1998; as
///                 scipy's scramble=True), for lhs it has its own permutations and jitter.
///                 Replicates are i.i.d., so the spread of a statistic across them gives
///                 its interval, and a run can grow replicate by replicate (--until).
///   saltelli_base N : the radial (Saltelli 2010) layout for Sobol sensitivity indices:
///                 sample i = m * N + j is row j of matrix m, where m = 0 is A, m = 1 is B
///                 and m = 2 + g is A with the dimensions of group g taken from B. Group g
///                 is dimension g; with saltelli_noise_group the last group (g = dimension)
///                 is the within-sample randomness, whose key stream_index() gives: A's for
///                 A and every AB_g but the noise group's, B's for B and AB_noise; with
///                 saltelli_noise_sources S > 1 the groups g = dimension .. dimension + S - 1
///                 are its S sources, each keyed by stream_index(i, s). A and B
///                 are the two halves of one design of 2 x dimension over N points.
///                 saltelli_extra_groups appends closed groups of several dimensions (a
///                 tolerance's amplitude, phase and per-bearing columns together): group
///                 g = dimension (+ 1 with the noise group) + e takes every dimension of
///                 extra group e from B, and keys its own randomness like A.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace poise::sampling {

enum class SamplingMethod { kMonteCarlo, kLatinHypercube, kSobol };

struct DesignOptions {
  std::size_t replicate_size = 0;  ///< 0: one design of all samples
  std::size_t saltelli_base = 0;   ///< 0: no sensitivity layout
  bool saltelli_noise_group = false;
  /// Sources of the within-sample randomness, each with its own stream and its own group
  /// (per-test draws, measurement noise); 1 = all of it one group.
  std::size_t saltelli_noise_sources = 1;
  std::vector<std::vector<std::size_t>> saltelli_extra_groups;  ///< closed groups of dimensions
  bool scramble = false;                                        ///< sobol: linear matrix scramble (set for replicates)
};

SamplingMethod parse_sampling_method(std::string_view name);  // "monte_carlo", "lhs", "sobol"
std::string to_string(SamplingMethod method);

class Design {
 public:
  Design(SamplingMethod method, std::uint64_t seed, std::size_t n_samples, std::size_t dimension,
         const DesignOptions& options = {});

  /// Fills u (size dimension()) with the design point of sample i, each in (0, 1).
  /// Thread-safe.
  void point(std::size_t i, std::span<double> u) const;

  std::size_t dimension() const { return dimension_; }
  std::size_t size() const { return n_samples_; }
  SamplingMethod method() const { return method_; }
  const DesignOptions& options() const { return options_; }

  /// The key of sample i's own random streams (procedure draws, noise): i itself, except
  /// in the Saltelli layout (see above).
  std::uint64_t stream_index(std::size_t i) const { return stream_index(i, 0); }
  /// The key of sample i's within-sample randomness source `source` (< saltelli_noise_sources):
  /// B's in B and in that source's own group, A's elsewhere; i without the Saltelli layout.
  std::uint64_t stream_index(std::size_t i, std::size_t source) const;
  /// Groups of the within-sample randomness in the Saltelli layout (0 without it).
  std::size_t noise_groups() const {
    return options_.saltelli_noise_group ? std::max<std::size_t>(options_.saltelli_noise_sources, 1) : 0;
  }
  /// Saltelli layout: the number of groups (dimension, plus one for the noise group).
  std::size_t saltelli_groups() const { return dimension_ + noise_groups() + options_.saltelli_extra_groups.size(); }

 private:
  struct Replicates;  // lazily built designs of the replicates, shared by copies
  SamplingMethod method_;
  std::uint64_t seed_;
  std::size_t n_samples_;
  std::size_t dimension_;
  std::vector<std::vector<std::uint32_t>> lhs_permutation_;  // [dimension][sample]
  std::vector<std::uint64_t> sobol_shift_;                   // [dimension]
  std::vector<std::uint64_t> sobol_scramble_;                // [dimension][64] row masks
  DesignOptions options_;
  std::shared_ptr<Replicates> replicates_;
  std::shared_ptr<const Design> saltelli_base_;  // 2 x dimension, N points
};

}  // namespace poise::sampling
