// The sample loop (engine/run/sample_driver.h): the split of an MPI round into portions, rank
// 0's balanced share, and in one process the order, prepared bytes and stop points the sink sees,
// the same for any thread count. (Several ranks: tests/cli/reliability_test.cc, Mpi.*.)
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "engine/run/sample_driver.h"

namespace poise::engine {
namespace {

struct Sample {
  std::size_t index = 0;
  bool ok = true;
  std::string message;
  double value = 0.0;
};

TEST(RoundPortions, CoverTheRoundInRankOrderWithRankZerosShare) {
  // 8 chunks of 10 from 100, the last one cut at 177; rank 0 takes a quarter, the others the
  // rest as evenly as possible.
  const auto p = detail::round_portions(100, 177, 10, 8, 3, 0.25);
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[0].start, 100u);
  EXPECT_EQ(p[0].n, 20u);
  EXPECT_EQ(p[1].start, 120u);
  EXPECT_EQ(p[1].n, 30u);
  EXPECT_EQ(p[2].start, 150u);
  EXPECT_EQ(p[2].n, 27u);  // 3 chunks, the last cut at the end of the run
  // Shares that do not divide evenly: 5 chunks left over for 2 other ranks go 3 and 2.
  const auto q = detail::round_portions(0, 1000, 10, 7, 3, 0.3);
  EXPECT_EQ(q[0].n, 20u);
  EXPECT_EQ(q[1].n, 30u);
  EXPECT_EQ(q[2].n, 20u);
  EXPECT_EQ(q[2].start + q[2].n, 70u);
  // No share: rank 0 computes nothing, and its empty portion is where the round starts.
  const auto r = detail::round_portions(40, 1000, 10, 4, 2, 0.0);
  EXPECT_EQ(r[0].n, 0u);
  EXPECT_EQ(r[0].start, 40u);
  EXPECT_EQ(r[1].start, 40u);
  EXPECT_EQ(r[1].n, 40u);
  // One rank takes the whole round whatever its share.
  EXPECT_EQ(detail::round_portions(0, 1000, 10, 4, 1, 0.1)[0].n, 40u);
}

TEST(BalancedRootShare, GivesRankZeroAsMuchWorkAsEachOtherRank) {
  EXPECT_DOUBLE_EQ(detail::balanced_root_share(1.0, 0.0, 1.0, 4), 0.25);  // nothing to write: even shares
  EXPECT_DOUBLE_EQ(detail::balanced_root_share(0.0, 1.0, 1.0, 2), 0.5);   // not measured yet: even
  EXPECT_DOUBLE_EQ(detail::balanced_root_share(1.0, 1.0, 1.0, 2), 0.0);   // writing takes all its time
  for (const int ranks : {2, 3, 8}) {
    for (const double sink : {0.01, 0.05, 0.1}) {
      for (const double other : {0.3, 0.45}) {  // the others also encode and send: dearer per sample
        const double compute = 0.3;
        const double share = detail::balanced_root_share(compute, sink, other, ranks);
        const double root_work = share * compute + sink;  // per sample of the round
        const double other_work = (1.0 - share) / (ranks - 1) * other;
        if (share > 0.0) {
          EXPECT_NEAR(root_work, other_work, 1e-12) << ranks << " ranks, sink " << sink;
        } else {  // writing alone takes rank 0 longer than the others' computing
          EXPECT_GE(root_work, other_work) << ranks << " ranks, sink " << sink;
        }
      }
    }
  }
}

TEST(BalancedRootShare, CountsTheWritingOfTheRoundBeforeBesideThisOnesComputing) {
  // Rank 0 writes the round before (M samples) while computing its share of this one (N): with
  // M = N / 2 it writes half as much beside the same computing, so its share grows.
  const double compute = 0.3, sink = 0.1, other = 0.35;
  for (const double ratio : {0.5, 1.0, 4.0 / 3.0}) {
    const double share = detail::balanced_root_share(compute, sink, other, 2, ratio);
    EXPECT_NEAR(share * compute + ratio * sink, (1.0 - share) * other, 1e-12) << ratio;
  }
  EXPECT_GT(detail::balanced_root_share(compute, sink, other, 2, 0.5),
            detail::balanced_root_share(compute, sink, other, 2, 1.0));
  EXPECT_EQ(detail::balanced_root_share(compute, sink, other, 2, 4.0), 0.0);  // writing alone is longer
}

TEST(ChunksPerRank, ShortFirstRoundsThenAQuarterOfWhatIsLeftAtMostTheCap) {
  EXPECT_EQ(detail::chunks_per_rank(0, 1000, 2), 1u);  // before any timing
  EXPECT_EQ(detail::chunks_per_rank(1, 1000, 2), 1u);
  EXPECT_EQ(detail::chunks_per_rank(2, 1000, 2), detail::kChunksPerRankInARound);
  EXPECT_EQ(detail::chunks_per_rank(5, 48, 2), 6u);  // 48 / (4 x 2)
  EXPECT_EQ(detail::chunks_per_rank(5, 3, 2), 1u);    // never none
  // Towards the end each round is about 3/4 of the one before.
  std::size_t left = 400, before = 0;
  for (std::size_t r = 2; left > 0; ++r) {
    const std::size_t n = std::min(left, 2 * detail::chunks_per_rank(r, left, 2));
    if (before > 0 && n > 8) {
      EXPECT_GE(static_cast<double>(n), 0.7 * static_cast<double>(before)) << left;
    }
    before = n, left -= n;
  }
}

// One process: every sample sunk once, in order, chunk by chunk with that chunk's prepared
// bytes; a stop at the first chunk boundary past 45 samples.
std::vector<std::string> drive(int threads, std::size_t* completed) {
  std::vector<std::string> seen;
  const DriveSpec spec{5, 100, 10, 3, threads, false};
  const DriveOutcome out = drive_samples<Sample>(
      spec, [] { return 0; },
      [](std::size_t i, int&, Sample& s) {
        s.index = i;
        s.value = 0.5 * static_cast<double>(i);
      },
      [](std::span<const Sample> chunk) { return std::to_string(chunk.front().index) + "+" + std::to_string(chunk.size()); },
      [&](std::size_t first, std::span<const Sample> chunk, std::string_view prepared) {
        for (std::size_t k = 0; k < chunk.size(); ++k) EXPECT_EQ(chunk[k].index, first + k);
        EXPECT_EQ(prepared, std::to_string(first) + "+" + std::to_string(chunk.size()));
        seen.emplace_back(prepared);
      },
      [](std::size_t done) { return done > 45 ? std::string("enough") : std::string(); },
      [](const Sample&, ByteWriter&) {}, [](ByteReader&, Sample&) {});
  *completed = out.completed;
  EXPECT_EQ(out.stop_reason, "enough");
  return seen;
}

TEST(DriveSamples, SinksEveryChunkInOrderWithItsPreparedBytesAndStopsAtAChunkBoundary) {
  std::size_t one = 0, two = 0;
  const std::vector<std::string> a = drive(1, &one), b = drive(2, &two);
  EXPECT_EQ(one, 55u);  // chunks from 5: 5-14, ..., 45-54; the stop rule is met after 55
  EXPECT_EQ(a, (std::vector<std::string>{"5+10", "15+10", "25+10", "35+10", "45+10"}));
  EXPECT_EQ(a, b);
  EXPECT_EQ(two, one);
}

}  // namespace
}  // namespace poise::engine
