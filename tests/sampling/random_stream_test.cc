// Tests of the counter-based random streams (src/sampling/random_stream.h).
#include "sampling/random_stream.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <vector>

namespace {

using poise::sampling::RandomStream;
using poise::sampling::StreamId;
using poise::sampling::to_open_unit;

// Random123 known-answer vectors for philox4x64_10 (Random123 distribution, tests/kat_vectors;
// the same three vectors are quoted by several independent Philox implementations).
struct Kat {
  std::array<std::uint64_t, 4> ctr;
  std::array<std::uint64_t, 2> key;
  std::array<std::uint64_t, 4> out;
};

TEST(Philox, KnownAnswerVectors) {
  constexpr std::uint64_t f = ~0ull;
  const Kat kats[] = {
      {{0, 0, 0, 0}, {0, 0}, {0x16554d9eca36314cull, 0xdb20fe9d672d0fdcull, 0xd7e772cee186176bull, 0x7e68b68aec7ba23bull}},
      {{f, f, f, f}, {f, f}, {0x87b092c3013fe90bull, 0x438c3c67be8d0224ull, 0x9cc7d7c69cd777b6ull, 0xa09caebf594f0ba0ull}},
      {{0x243f6a8885a308d3ull, 0x13198a2e03707344ull, 0xa4093822299f31d0ull, 0x082efa98ec4e6c89ull},
       {0x452821e638d01377ull, 0xbe5466cf34e90c6cull},
       {0xa528f45403e61d95ull, 0x38c72dbd566e9788ull, 0xa5a1610e72fd18b5ull, 0x57bd43b5e52b7fe6ull}},
  };
  for (const Kat& k : kats) {
    r123::Philox4x64::ctr_type ctr = {{k.ctr[0], k.ctr[1], k.ctr[2], k.ctr[3]}};
    r123::Philox4x64::key_type key = {{k.key[0], k.key[1]}};
    const auto out = r123::Philox4x64()(ctr, key);
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(out.v[i], k.out[static_cast<std::size_t>(i)]) << "word " << i;
    }
  }
}

TEST(RandomStream, WordsAreThePhiloxBlocksOfTheDocumentedCounter) {
  // Word k of stream (seed, id, index) is word k % 4 of Philox(ctr = {index, k / 4, 0, 0},
  // key = {seed, id}).
  const std::uint64_t seed = 0x0123456789abcdefull, index = 987654321;
  RandomStream rs(seed, StreamId::kProcedure, index);
  for (std::uint64_t k = 0; k < 40; ++k) {
    r123::Philox4x64::ctr_type ctr = {{index, k / 4, 0, 0}};
    r123::Philox4x64::key_type key = {{seed, static_cast<std::uint64_t>(StreamId::kProcedure)}};
    EXPECT_EQ(rs.next_bits(), r123::Philox4x64()(ctr, key).v[k % 4]) << k;
  }
}

std::vector<std::uint64_t> draw(std::uint64_t seed, StreamId id, std::uint64_t index, int n) {
  RandomStream rs(seed, id, index);
  std::vector<std::uint64_t> v;
  for (int i = 0; i < n; ++i) v.push_back(rs.next_bits());
  return v;
}

TEST(RandomStream, SameKeyGivesSameSequence) {
  EXPECT_EQ(draw(42, StreamId::kDesign, 7, 101), draw(42, StreamId::kDesign, 7, 101));
  // Copies continue identically.
  RandomStream a(42, StreamId::kDesign, 7);
  for (int i = 0; i < 5; ++i) a.next_bits();
  RandomStream b = a;
  for (int i = 0; i < 20; ++i) EXPECT_EQ(a.next_bits(), b.next_bits());
}

TEST(RandomStream, DifferentKeysGiveDifferentSequences) {
  const auto base = draw(42, StreamId::kDesign, 7, 64);
  const std::vector<std::vector<std::uint64_t>> others = {
      draw(42, StreamId::kDesign, 8, 64), draw(43, StreamId::kDesign, 7, 64),
      draw(42, StreamId::kProcedure, 7, 64), draw(42, StreamId::kLhsJitter, 7, 64)};
  for (const auto& o : others) {
    // Not merely different somewhere: no word coincides (chance of any 64-bit match here ~2^-56).
    for (std::size_t i = 0; i < base.size(); ++i) EXPECT_NE(base[i], o[i]) << i;
  }
  // Within a stream all words are distinct.
  const auto longer = draw(1, StreamId::kDesign, 0, 4000);
  EXPECT_EQ(std::set<std::uint64_t>(longer.begin(), longer.end()).size(), longer.size());
}

TEST(RandomStream, BitsAtIsRandomAccessToNextBits) {
  RandomStream seq(2024, StreamId::kLhsPermutation, 3);
  const RandomStream ra(2024, StreamId::kLhsPermutation, 3);
  std::vector<std::uint64_t> words;
  for (std::uint64_t k = 0; k < 37; ++k) words.push_back(seq.next_bits());
  // In reverse order, to show bits_at does not depend on position or history.
  for (std::uint64_t k = 37; k-- > 0;) EXPECT_EQ(ra.bits_at(k), words[k]) << k;
  // bits_at does not advance the stream.
  RandomStream fresh(2024, StreamId::kLhsPermutation, 3);
  (void)fresh.bits_at(5);
  EXPECT_EQ(fresh.next_bits(), words[0]);
  // Far ahead.
  RandomStream far(2024, StreamId::kLhsPermutation, 3);
  std::uint64_t w = 0;
  for (int k = 0; k <= 1001; ++k) w = far.next_bits();
  EXPECT_EQ(ra.bits_at(1001), w);
}

TEST(RandomStream, UniformIsStrictlyInsideUnitInterval) {
  double sum = 0.0, sum2 = 0.0;
  const int n = 100000;
  RandomStream rs(7, StreamId::kProcedure, 0);
  for (int i = 0; i < n; ++i) {
    const double u = rs.uniform();
    ASSERT_GT(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    sum2 += u * u;
  }
  // Mean 1/2 (sd of the mean 0.00091) and variance 1/12 (sd of the estimate 0.00024):
  // tolerances at about 5 standard errors.
  const double mean = sum / n;
  EXPECT_NEAR(mean, 0.5, 0.005);
  EXPECT_NEAR(sum2 / n - mean * mean, 1.0 / 12.0, 0.0012);
}

TEST(RandomStream, ToOpenUnitEnds) {
  EXPECT_GT(to_open_unit(0), 0.0);
  // The largest input must still map strictly below 1: a 1.0 fed to a normal quantile
  // gives +inf (or a Boost overflow_error).
  EXPECT_LT(to_open_unit(~0ull), 1.0);
  EXPECT_LT(to_open_unit(0xfffffffffffff800ull), 1.0);
  // Every 2^-53 grid value maps into (0, 1) and the map is non-decreasing over a sweep of the
  // top of the range, where rounding would first bite.
  double prev = 0.0;
  for (std::uint64_t m = (1ull << 53) - 4096; m < (1ull << 53); ++m) {
    const double x = to_open_unit(m << 11);
    EXPECT_GT(x, 0.0);
    EXPECT_LT(x, 1.0) << "m = " << m;
    EXPECT_GE(x, prev);
    prev = x;
  }
  // Symmetry of an exact midpoint map: x(~bits) = 1 - x(bits). For bits < 2^63, x(~bits) is in
  // [1/2, 1) where 1 - x is exact, so this compares without rounding.
  for (std::uint64_t b : {0ull, 12345ull << 11, 0x0123456789abcdefull, 0x7ff0000000000000ull}) {
    EXPECT_EQ(1.0 - to_open_unit(~b), to_open_unit(b)) << std::hex << b;
  }
}

}  // namespace
