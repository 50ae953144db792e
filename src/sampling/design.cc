#include "sampling/design.h"

#include <algorithm>
#include <bit>
#include <boost/random/sobol.hpp>
#include <mutex>
#include <numeric>

#include "core/error.h"
#include "sampling/random_stream.h"

namespace poise::sampling {

namespace {

// Point i of the Sobol sequence in u.size() dimensions: linearly scrambled with the rows of
// `scramble` (none when empty), then digitally shifted by `shift`.
void sobol_point(std::size_t i, std::span<const std::uint64_t> shift, std::span<const std::uint64_t> scramble,
                 std::span<double> u) {
  const std::size_t dimension = u.size();
  if (dimension == 0) return;
  // One engine per thread, re-positioned to point i (Gray-code jump, O(dim*64)).
  // Boost's seed(k) positions the engine so that its next vector is point k+1; point 0
  // is the origin, which the digital shift moves off zero.
  thread_local boost::random::sobol engine(1);
  if (engine.dimension() != dimension) engine = boost::random::sobol(dimension);
  if (i > 0) engine.seed(static_cast<boost::uint_least64_t>(i) - 1);
  for (std::size_t d = 0; d < dimension; ++d) {
    std::uint64_t raw = i > 0 ? static_cast<std::uint64_t>(engine()) : 0;
    if (!scramble.empty()) {
      std::uint64_t y = 0;
      for (int k = 0; k < 64; ++k) {
        const auto bit =
            static_cast<std::uint64_t>(std::popcount(raw & scramble[d * 64 + static_cast<std::size_t>(k)]) & 1);
        y |= bit << (63 - k);
      }
      raw = y;
    }
    u[d] = to_open_unit(raw ^ shift[d]);
  }
}

}  // namespace

SamplingMethod parse_sampling_method(std::string_view name) {
  if (name == "monte_carlo") return SamplingMethod::kMonteCarlo;
  if (name == "lhs") return SamplingMethod::kLatinHypercube;
  if (name == "sobol") return SamplingMethod::kSobol;
  throw Error("unknown sampling method \"" + std::string(name) + "\"; expected \"monte_carlo\", \"lhs\" or \"sobol\"");
}

std::string to_string(SamplingMethod method) {
  switch (method) {
    case SamplingMethod::kMonteCarlo: return "monte_carlo";
    case SamplingMethod::kLatinHypercube: return "lhs";
    case SamplingMethod::kSobol: return "sobol";
  }
  return "?";
}

struct Design::Replicates {
  std::mutex mutex;
  std::vector<std::shared_ptr<const Design>> designs;  // [replicate], built on first use
};

Design::Design(SamplingMethod method, std::uint64_t seed, std::size_t n_samples, std::size_t dimension,
               const DesignOptions& options)
    : method_(method), seed_(seed), n_samples_(n_samples), dimension_(dimension), options_(options) {
  require(n_samples > 0, "a design needs at least one sample");
  require(options.replicate_size == 0 || options.saltelli_base == 0,
          "a design has replicates or the Saltelli layout, not both");
  if (options.replicate_size > 0) {
    require(method != SamplingMethod::kSobol || std::has_single_bit(options.replicate_size),
            "a Sobol replicate needs a power of two points, got " + std::to_string(options.replicate_size));
    replicates_ = std::make_shared<Replicates>();
    return;
  }
  if (options.saltelli_base > 0) {
    const std::size_t groups = saltelli_groups();
    require(n_samples == options.saltelli_base * (groups + 2), "the Saltelli layout needs base x (groups + 2) samples");
    for (const auto& g : options.saltelli_extra_groups) {
      for (std::size_t d : g) require(d < dimension, "a Saltelli group names a dimension past the design's");
    }
    saltelli_base_ = std::make_shared<const Design>(method, seed, options.saltelli_base, 2 * dimension);
    return;
  }
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
    require(
        dimension <= boost::random::default_sobol_table::max_dimension,
        "Sobol design limited to " + std::to_string(boost::random::default_sobol_table::max_dimension) + " dimensions");
    RandomStream rs(seed, StreamId::kSobolShift, 0);
    sobol_shift_.resize(dimension);
    for (auto& s : sobol_shift_) s = rs.next_bits();
    if (options.scramble) {
      // Row k of the lower-triangular matrix (bit 63 - k is the k-th most significant):
      // random bits above bit 63 - k (the more significant input bits), 1 on the diagonal.
      RandomStream ls(seed, StreamId::kSobolScramble, 0);
      sobol_scramble_.resize(dimension * 64);
      for (std::size_t d = 0; d < dimension; ++d) {
        for (int k = 0; k < 64; ++k) {
          const std::uint64_t diag = std::uint64_t{1} << (63 - k);
          const std::uint64_t above = k == 0 ? 0 : ~((diag << 1) - 1);
          sobol_scramble_[d * 64 + static_cast<std::size_t>(k)] = (ls.next_bits() & above) | diag;
        }
      }
    }
  }
}

std::uint64_t Design::stream_index(std::size_t i, std::size_t source) const {
  if (!saltelli_base_) return i;
  const std::size_t n = options_.saltelli_base, m = i / n, j = i % n;
  const bool from_b = m == 1 || (source < noise_groups() && m == 2 + dimension_ + source);
  // B's keys lie above every index of the run, apart from A's.
  return from_b ? n_samples_ + j : j;
}

void Design::point(std::size_t i, std::span<double> u) const {
  if (u.size() != dimension_) throw Error("design point buffer has the wrong size");  // per sample: no string
  if (replicates_) {
    const std::size_t m = options_.replicate_size, r = i / m;
    // The last replicate this thread used (holding its owner alive, so no other design
    // can reuse the owner's address while it is cached).
    thread_local std::shared_ptr<Replicates> last_owner;
    thread_local std::size_t last_r = 0;
    thread_local std::shared_ptr<const Design> last;
    if (last_owner != replicates_ || last_r != r || !last) {
      std::lock_guard lock(replicates_->mutex);
      auto& designs = replicates_->designs;
      if (designs.size() <= r) designs.resize(r + 1);
      if (!designs[r]) {
        DesignOptions inner;
        inner.scramble = method_ == SamplingMethod::kSobol;
        const std::uint64_t seed_r = RandomStream(seed_, StreamId::kReplicateSeed, r).next_bits();
        designs[r] = std::make_shared<const Design>(method_, seed_r, m, dimension_, inner);
      }
      last = designs[r];
      last_owner = replicates_;
      last_r = r;
    }
    last->point(i % m, u);
    return;
  }
  if (saltelli_base_) {
    const std::size_t n = options_.saltelli_base, m = i / n, j = i % n;
    thread_local std::vector<double> ab;
    ab.resize(2 * dimension_);
    saltelli_base_->point(j, ab);
    const std::size_t first_extra = 2 + dimension_ + noise_groups();
    const std::vector<std::size_t>* extra =
        m >= first_extra ? &options_.saltelli_extra_groups[m - first_extra] : nullptr;
    for (std::size_t d = 0; d < dimension_; ++d) {
      const bool from_b = m == 1 || m == 2 + d || (extra && std::find(extra->begin(), extra->end(), d) != extra->end());
      u[d] = ab[from_b ? dimension_ + d : d];
    }
    return;
  }
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
        u[d] = std::min((static_cast<double>(lhs_permutation_[d][i]) + rs.uniform()) / n, 1.0 - 0x1.0p-53);
      }
      break;
    }
    case SamplingMethod::kSobol: sobol_point(i, sobol_shift_, sobol_scramble_, u); break;
  }
}

}  // namespace poise::sampling
