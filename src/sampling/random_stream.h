#pragma once
/// Counter-based random streams (Random123 Philox4x64-10). A stream is a pure
/// function of (seed, stream id, sample index): the same numbers for any thread
/// or process count, and any sample can be replayed alone. No global RNG.
#include <Random123/philox.h>

#include <cstdint>

namespace poise::sampling {

/// Stream ids keep independent uses of one seed apart.
enum class StreamId : std::uint64_t {
  kDesign = 1,  ///< plain Monte Carlo design points
  kLhsPermutation = 2,
  kLhsJitter = 3,
  kSobolShift = 4,
  kReplicateSeed = 5,  ///< seed of each randomized replicate of a design
  kSobolScramble = 6,  ///< linear matrix scramble of a Sobol replicate
  kProcedure = 16,     ///< randomness inside a sample's procedure (noise etc.)
  kNoise = 17,         ///< measurement noise, apart from the procedure's other draws
  kBootstrap = 18,     ///< bootstrap resampling of results
};

/// Maps 64 random bits to a double in the open interval (0, 1): the top 52 bits, centred
/// in their cell, exact in double precision, within [2^-53, 1 - 2^-53] and symmetric.
inline double to_open_unit(std::uint64_t bits) { return (static_cast<double>(bits >> 12) + 0.5) * 0x1.0p-52; }

/// A sequence of random numbers keyed by (seed, stream, index).
class RandomStream {
 public:
  using Philox = r123::Philox4x64;

  RandomStream(std::uint64_t seed, StreamId stream, std::uint64_t index)
      : key_{{seed, static_cast<std::uint64_t>(stream)}}, ctr_{{index, 0, 0, 0}} {}

  /// Next 64 random bits.
  std::uint64_t next_bits() {
    if (pos_ == 4) {
      block_ = Philox()(ctr_, key_);
      ++ctr_.v[1];
      pos_ = 0;
    }
    return block_.v[pos_++];
  }
  /// Next uniform in (0, 1).
  double uniform() { return to_open_unit(next_bits()); }

  /// The k-th 64-bit word of this stream without advancing (random access).
  std::uint64_t bits_at(std::uint64_t k) const {
    Philox::ctr_type c = ctr_;
    c.v[1] = k / 4;
    return Philox()(c, key_).v[k % 4];
  }

 private:
  Philox::key_type key_;
  Philox::ctr_type ctr_;
  Philox::ctr_type block_{};
  int pos_ = 4;
};

}  // namespace poise::sampling
