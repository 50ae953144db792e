// Field statistics read column by column (engine/results/field_statistics.h) against the whole field
// in memory: sampling::summarize of every value and sampling::quantile_value of each column.
#include <gtest/gtest.h>

#include <cmath>
#include <condition_variable>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "engine/results/field_statistics.h"
#include "sampling/statistics.h"

namespace poise {
namespace {

using engine::field_statistics;

// A field [rows][columns] with NaN holes (failed samples), ties and negative values.
std::vector<std::vector<float>> make_field(std::size_t rows, std::size_t columns, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::lognormal_distribution<double> big(1.0, 0.8);
  std::normal_distribution<double> small(0.0, 1e-3);
  std::vector<std::vector<float>> col(columns, std::vector<float>(rows));
  for (std::size_t p = 0; p < columns; ++p) {
    for (std::size_t r = 0; r < rows; ++r) {
      double v = p % 5 == 0 ? small(rng) : big(rng) * (1.0 + 0.1 * static_cast<double>(p));
      if (p % 7 == 3) v = std::round(v * 4.0) / 4.0;  // many equal values
      col[p][r] = r % 97 == 13 ? NAN : static_cast<float>(v);
    }
  }
  return col;
}

void expect_same_estimate(const sampling::Estimate& a, const sampling::Estimate& b, double rel, const char* what) {
  EXPECT_NEAR(a.value, b.value, rel * std::abs(b.value) + 1e-300) << what;
  ASSERT_EQ(a.lo.has_value(), b.lo.has_value()) << what;
  ASSERT_EQ(a.hi.has_value(), b.hi.has_value()) << what;
  if (a.lo) {
    EXPECT_NEAR(*a.lo, *b.lo, rel * std::abs(*b.lo) + 1e-300) << what;
  }
  if (a.hi) {
    EXPECT_NEAR(*a.hi, *b.hi, rel * std::abs(*b.hi) + 1e-300) << what;
  }
}

TEST(FieldStatistics, EqualTheStatisticsOfTheWholeFieldInMemory) {
  const std::size_t rows = 5003, columns = 23;
  const auto field = make_field(rows, columns, 7);
  const double quantiles[] = {0.5, 0.95, 0.9973};
  std::vector<double> all;
  for (const auto& c : field) {
    for (float f : c) {
      if (!std::isnan(f)) all.push_back(f);
    }
  }
  const sampling::Summary want = sampling::summarize(all);
  // Columns read into the scratch (from a file) for 1 and 3 threads, viewed in place (kept in
  // memory) for 2; the pooled order statistics from collected values, or from counts (limit 0).
  for (const auto& [threads, collect_limit] : {std::pair<int, std::size_t>{1, engine::kFieldCollectLimit},
                                               {2, engine::kFieldCollectLimit}, {3, 0}, {2, 0}}) {
    const auto got = field_statistics(
        columns,
        [&, in_memory = threads == 2](std::size_t p, std::vector<float>& out) -> std::span<const float> {
          if (in_memory) return field[p];
          out = field[p];
          return out;
        },
        quantiles, threads, collect_limit);
    EXPECT_EQ(got.pooled.n, want.n);
    // Order statistics are selected exactly: equal to the last bit.
    EXPECT_EQ(got.pooled.p50.value, want.p50.value);
    EXPECT_EQ(got.pooled.p95.lo, want.p95.lo);
    EXPECT_EQ(got.pooled.p95.hi, want.p95.hi);
    EXPECT_EQ(got.pooled.p99_73.value, want.p99_73.value);
    EXPECT_EQ(got.pooled.max.value, want.max.value);
    EXPECT_EQ(got.pooled.max.lo, want.max.lo);
    // Sums in another order: equal to rounding.
    expect_same_estimate(got.pooled.mean, want.mean, 1e-12, "mean");
    expect_same_estimate(got.pooled.std, want.std, 1e-10, "std");
    expect_same_estimate(got.pooled.p50, want.p50, 0, "p50");
    for (std::size_t p = 0; p < columns; ++p) {
      std::vector<double> column;
      for (float f : field[p]) {
        if (!std::isnan(f)) column.push_back(f);
      }
      for (std::size_t q = 0; q < 3; ++q) {
        std::vector<double> copy = column;
        EXPECT_EQ(got.per_point[q][p], sampling::quantile_value(copy, quantiles[q])) << "point " << p;
      }
    }
  }
}

TEST(FieldStatistics, AFieldOfFewDistinctValuesByCountsAsByCollection) {
  // Every value in one of five bins: the wanted bins hold most of the field.
  std::vector<std::vector<float>> field(7, std::vector<float>(3001));
  for (std::size_t p = 0; p < field.size(); ++p) {
    for (std::size_t i = 0; i < field[p].size(); ++i) {
      field[p][i] = static_cast<float>((i * 7 + p) % 5) * 0.25f + 1.0f;
    }
  }
  const double quantiles[] = {0.5, 0.99};
  auto run = [&](std::size_t limit) {
    return field_statistics(
        field.size(), [&](std::size_t p, std::vector<float>&) -> std::span<const float> { return field[p]; },
        quantiles, 2, limit);
  };
  const auto collected = run(engine::kFieldCollectLimit), counted = run(0), capped = run(100);
  std::vector<double> all;
  for (const auto& c : field) all.insert(all.end(), c.begin(), c.end());
  const sampling::Summary want = sampling::summarize(all);
  for (const auto* got : {&collected, &counted, &capped}) {
    EXPECT_EQ(got->pooled.n, want.n);
    EXPECT_EQ(got->pooled.p50.value, want.p50.value);
    EXPECT_EQ(got->pooled.p95.lo, want.p95.lo);
    EXPECT_EQ(got->pooled.p99_73.value, want.p99_73.value);
    EXPECT_EQ(got->pooled.max.value, want.max.value);
    EXPECT_EQ(got->per_point, collected.per_point);
  }
}

TEST(FieldStatistics, SameFiguresForAnyThreadCount) {
  const auto field = make_field(2000, 31, 11);
  const double quantiles[] = {0.95};
  auto run = [&](int threads) {
    return field_statistics(
        31, [&](std::size_t p, std::vector<float>&) -> std::span<const float> { return field[p]; }, quantiles, threads);
  };
  const auto a = run(1), b = run(4);
  EXPECT_EQ(a.pooled.mean.value, b.pooled.mean.value);  // bit for bit
  EXPECT_EQ(a.pooled.std.value, b.pooled.std.value);
  EXPECT_EQ(a.per_point, b.per_point);
}

// The ranks of an MPI run, played by threads: all_gather waits for every rank's bytes and
// hands each the lot, in rank order.
class ThreadRanks {
 public:
  explicit ThreadRanks(int ranks) : ranks_(ranks), bytes_(static_cast<std::size_t>(ranks)) {}
  std::vector<std::string> all_gather(int rank, const std::string& mine) {
    std::unique_lock<std::mutex> lock(mutex_);
    const std::size_t round = round_;
    bytes_[static_cast<std::size_t>(rank)] = mine;
    if (++arrived_ == ranks_) {
      result_ = bytes_;
      arrived_ = 0;
      ++round_;
      done_.notify_all();
    } else {
      done_.wait(lock, [&] { return round_ != round; });
    }
    return result_;
  }

 private:
  int ranks_, arrived_ = 0;
  std::size_t round_ = 0;
  std::vector<std::string> bytes_, result_;
  std::mutex mutex_;
  std::condition_variable done_;
};

TEST(FieldStatistics, SharedAmongRanksEveryRankGetsOneProcesssFiguresBitForBit) {
  const std::size_t columns = 23;
  const auto field = make_field(3001, columns, 5);
  const double quantiles[] = {0.5, 0.95, 0.9973};
  const engine::FieldColumnSource column = [&](std::size_t p, std::vector<float>& scratch) -> std::span<const float> {
    scratch = field[p];  // as read from a file
    return scratch;
  };
  for (const std::size_t collect_limit : {engine::kFieldCollectLimit, std::size_t{0}}) {
    const engine::FieldStatistics one = field_statistics(columns, column, quantiles, 2, collect_limit);
    for (const int ranks : {2, 3, 5}) {
      ThreadRanks exchange(ranks);
      std::vector<engine::FieldStatistics> got(static_cast<std::size_t>(ranks));
      std::vector<std::thread> threads;
      for (int r = 0; r < ranks; ++r) {
        threads.emplace_back([&, r] {
          engine::FieldShare share{r, ranks, [&, r](const std::string& mine) { return exchange.all_gather(r, mine); }};
          got[static_cast<std::size_t>(r)] = field_statistics(columns, column, quantiles, 1, collect_limit, &share);
        });
      }
      for (auto& t : threads) t.join();
      for (const auto& g : got) {
        EXPECT_EQ(g.per_point, one.per_point) << ranks << " ranks";
        EXPECT_EQ(g.pooled.n, one.pooled.n);
        EXPECT_EQ(g.pooled.mean.value, one.pooled.mean.value) << ranks << " ranks";  // bit for bit
        EXPECT_EQ(g.pooled.std.value, one.pooled.std.value);
        EXPECT_EQ(g.pooled.p95.value, one.pooled.p95.value);
        EXPECT_EQ(g.pooled.p99_73.value, one.pooled.p99_73.value);
        EXPECT_EQ(g.pooled.p99_73.lo, one.pooled.p99_73.lo);
        EXPECT_EQ(g.pooled.max.value, one.pooled.max.value);
      }
    }
  }
}

TEST(FieldStatistics, OneValueAndNoValue) {
  const double quantiles[] = {0.5};
  const std::vector<std::vector<float>> one = {{NAN, 2.5f, NAN}, {NAN, NAN, NAN}};
  const auto got = field_statistics(
      2, [&](std::size_t p, std::vector<float>&) -> std::span<const float> { return one[p]; }, quantiles, 2);
  EXPECT_EQ(got.pooled.n, 1u);
  EXPECT_EQ(got.pooled.p50.value, 2.5);
  EXPECT_EQ(got.pooled.max.value, 2.5);
  EXPECT_EQ(got.per_point[0][0], 2.5);
  EXPECT_TRUE(std::isnan(got.per_point[0][1]));
  const auto none = field_statistics(
      1,
      [](std::size_t, std::vector<float>& out) -> std::span<const float> {
        out.assign(4, NAN);
        return out;
      },
      quantiles, 1);
  EXPECT_EQ(none.pooled.n, 0u);
}

}  // namespace
}  // namespace poise
