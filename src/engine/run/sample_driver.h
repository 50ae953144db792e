#pragma once
/// The sample loop every study runs through: samples [first, total) in chunks of the sample
/// order, spread over the threads of each process and over MPI ranks (sampling/distributed.h),
/// handed to a sink on rank 0 in sample order (results stream to disk chunk by chunk).
/// After each chunk rank 0 may stop the run (a confidence interval reached its target, too
/// many samples failed); a signal (sampling/interrupt.h) stops it after the round in flight.
/// The decision points are chunk boundaries of the sample order, the same for any thread or
/// rank count, so a stopped run has the same samples whatever the machine.
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/error.h"
#include "engine/results/fault_injection.h"
#include "sampling/byte_message.h"
#include "sampling/distributed.h"
#include "sampling/interrupt.h"
#include "sampling/progress.h"

namespace poise::engine {

struct DriveSpec {
  std::size_t first = 0;  ///< samples before this are done (resume)
  std::size_t total = 0;  ///< samples planned (the cap under --until)
  std::size_t chunk = 1024;
  std::size_t grain = 16;  ///< samples per parallel task
  int threads = 1;
  /// Spread over the MPI ranks (the run's main loop); false for a rank's local work.
  bool distributed = false;
};

struct DriveOutcome {
  std::size_t completed = 0;  ///< samples [0, completed) are done and were sunk
  bool interrupted = false;   ///< a signal stopped the run
  int signal = 0;
  std::string stop_reason;  ///< why the stop callback ended the run ("" = it did not)
};

using sampling::ByteReader;
using sampling::ByteWriter;

/// The fields every sample result has (index, ok, message, inputs, outputs), for the
/// encode/decode of a result type.
template <class Result>
void encode_sample_fields(const Result& r, ByteWriter& w) {
  w.put(r.index);
  w.put(r.ok);
  w.put_string(r.message);
  w.put_vector(r.inputs);
  w.put_vector(r.outputs);
}
template <class Result>
void decode_sample_fields(ByteReader& rd, Result& r) {
  r.index = rd.get<std::size_t>();
  r.ok = rd.get<bool>();
  rd.get_string(r.message);
  rd.get_vector(r.inputs);
  rd.get_vector(r.outputs);
}

namespace detail {

/// The samples [start, start + n) one rank computes in a round.
struct Portion {
  std::size_t start = 0, n = 0;
};

/// A round of `chunks` chunks of the sample order from `base` (the last one may end at
/// `total`), in contiguous portions in rank order: rank 0 takes `root_share` of the chunks
/// (rounded), the other ranks the rest, as evenly as possible.
inline std::vector<Portion> round_portions(std::size_t base, std::size_t total, std::size_t chunk, std::size_t chunks,
                                           int ranks, double root_share) {
  const auto others = static_cast<std::size_t>(ranks - 1);
  auto root_chunks =
      static_cast<std::size_t>(std::lround(std::clamp(root_share, 0.0, 1.0) * static_cast<double>(chunks)));
  if (others == 0) root_chunks = chunks;
  const std::size_t rest = chunks - std::min(root_chunks, chunks);
  std::vector<Portion> portions(static_cast<std::size_t>(ranks));
  std::size_t at = base;
  for (std::size_t q = 0; q < portions.size(); ++q) {
    const std::size_t n_chunks = q == 0 ? chunks - rest : rest / others + ((q - 1) < rest % others ? 1 : 0);
    const std::size_t end = std::min(total, at + n_chunks * chunk);
    portions[q] = {at, end - at};
    at = end;
  }
  return portions;
}

/// Rank 0's share of a round's chunks that gives it as much work as each other rank, when it
/// also takes `sink_seconds_per_sample` for every sample of the round (receiving, writing) and
/// every rank computes (and formats) a sample in `compute_seconds_per_sample`: with s their
/// ratio and R ranks, rank 0 computes n0 = N (1 - (R - 1) s) / R of the round's N samples and
/// the others n0 + N s each; none when (R - 1) s >= 1.
inline double balanced_root_share(double compute_seconds_per_sample, double sink_seconds_per_sample, int ranks) {
  if (!(compute_seconds_per_sample > 0.0)) return 1.0 / ranks;
  const double s = sink_seconds_per_sample / compute_seconds_per_sample;
  return std::max(0.0, (1.0 - (ranks - 1) * s) / ranks);
}

/// Chunks per rank in a round of an MPI run: enough to balance rank 0's share finely.
inline constexpr std::size_t kChunksPerRankInARound = 4;

}  // namespace detail

/// The sample loop (drive_samples below): compute(i, workspace, result); prepare(span of
/// results) -> std::string, a chunk's bytes for the sink (samples.csv rows), made where the
/// chunk was computed, on its threads; sink(first_index, span of results, prepared bytes) on
/// rank 0 in order, chunk by chunk; stop(completed) on rank 0 after each chunk, returning a
/// reason to stop ("" to go on); encode(result, ByteWriter&) and decode(ByteReader&, result)
/// carry results between ranks. Rank 0's outcome is every rank's.
template <class Result, class MakeWorkspace, class Compute, class Prepare, class Sink, class Stop, class Encode,
          class Decode>
class SampleDriver {
 public:
  SampleDriver(const DriveSpec& spec, MakeWorkspace make_workspace, Compute compute, Prepare prepare, Sink sink,
               Stop stop, Encode encode, Decode decode, sampling::Progress* progress)
      : spec_(spec),
        compute_(std::move(compute)),
        prepare_(std::move(prepare)),
        sink_(std::move(sink)),
        stop_(std::move(stop)),
        encode_(std::move(encode)),
        decode_(std::move(decode)),
        progress_(progress),
        ranks_(spec.distributed ? sampling::Cluster::size() : 1),
        root_(!spec.distributed || sampling::Cluster::root()),
        chunk_(std::max<std::size_t>(spec.chunk, 1)),
        arena_(std::max(1, spec.threads)),
        workspaces_(std::move(make_workspace)),
        inject_(fault_injection::failing_sample_period()) {
    out_.completed = spec.first;
  }

  DriveOutcome run() { return ranks_ == 1 ? run_alone() : run_distributed(); }

 private:
  using Workspace = decltype(std::declval<MakeWorkspace>()());
  // A portion's results and its chunks' prepared bytes.
  struct Computed {
    std::vector<Result> results;
    std::vector<std::string> prepared;
  };

  // Samples [first, first + n) on the arena's threads, then each chunk's bytes. Fault injection
  // for the tests of failure handling (engine/results/fault_injection.h): every k-th sample
  // (indices k-1, 2k-1, ...) fails as a solver failure would.
  void compute_portion(std::size_t first, std::size_t n, Computed& into) {
    if (into.results.size() < n) into.results.resize(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, std::max<std::size_t>(spec_.grain, 1)),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        Workspace& ws = workspaces_.local();
                        for (std::size_t k = r.begin(); k != r.end(); ++k) {
                          compute_(first + k, ws, into.results[k]);
                          if (inject_ > 0 && (first + k + 1) % inject_ == 0) {
                            into.results[k].ok = false;
                            into.results[k].message = "injected failure (fault_injection::fail_every_sample)";
                          }
                        }
                      });
    into.prepared.resize((n + chunk_ - 1) / chunk_);
    for (std::size_t c = 0; c < into.prepared.size(); ++c) {
      const std::size_t from = c * chunk_;
      into.prepared[c] = prepare_(std::span<const Result>(into.results.data() + from, std::min(chunk_, n - from)));
    }
  }

  // Rank 0: a portion's results sunk chunk by chunk, each followed by the stop rule; nothing
  // past a stop point is kept (computed, not sunk).
  void take(std::size_t start, std::span<const Result> results, std::span<const std::string> prepared) {
    for (std::size_t c = 0; c * chunk_ < results.size(); ++c) {
      if (stop_now_) return;
      const std::span<const Result> part = results.subspan(c * chunk_, std::min(chunk_, results.size() - c * chunk_));
      sink_(start + c * chunk_, part, std::string_view(prepared[c]));
      out_.completed = start + c * chunk_ + part.size();
      out_.stop_reason = stop_(out_.completed);
      stop_now_ = !out_.stop_reason.empty();
      if (progress_) progress_->update(out_.completed - spec_.first);
    }
  }

  // After a round: whether the run ends (rank 0's stop, a signal on any rank), the same on
  // every rank.
  bool round_ends() {
    if (root_ && sampling::interrupt_requested()) {
      out_.interrupted = true;
      out_.signal = sampling::interrupt_signal();
    }
    if (ranks_ == 1) return stop_now_ || out_.interrupted;
    const bool any_signal = sampling::Cluster::any(sampling::interrupt_requested());
    const bool end = sampling::Cluster::any(root_ && (stop_now_ || out_.interrupted));
    if (any_signal && root_ && !out_.interrupted && !stop_now_) {
      out_.interrupted = true;
      out_.signal = 15;
    }
    return end || any_signal;
  }

  // One process: chunk by chunk; the next chunk is computed (and prepared) on the arena's other
  // threads while this one is sunk (written, counted, checked by the stop rule) on the calling
  // thread, so that the writing does not leave the cores idle.
  DriveOutcome run_alone() {
    Computed now, ahead_results;
    tbb::task_group ahead;
    bool computed_ahead = false;
    for (std::size_t base = spec_.first; base < spec_.total; base += chunk_) {
      const std::size_t n = std::min(chunk_, spec_.total - base);
      if (!computed_ahead) arena_.execute([&] { compute_portion(base, n, now); });
      computed_ahead = false;
      const std::size_t next = base + chunk_;
      const bool pipelined = next < spec_.total;
      if (pipelined) {
        arena_.execute([&] {
          ahead.run([&, next] { compute_portion(next, std::min(chunk_, spec_.total - next), ahead_results); });
        });
      }
      try {
        take(base, std::span<const Result>(now.results.data(), n), now.prepared);
      } catch (...) {
        if (pipelined) arena_.execute([&] { ahead.wait(); });  // its buffers go out of scope
        throw;
      }
      if (pipelined) {
        arena_.execute([&] { ahead.wait(); });
        std::swap(now, ahead_results);
        computed_ahead = true;
      }
      if (round_ends()) break;
    }
    return out_;
  }

  // Several ranks: rounds of a few chunks per rank, each rank computing its portion; rank 0
  // receives and sinks the portions rank by rank, chunk by chunk (one chunk of another rank's
  // in memory at a time). Rank 0
  // times its own computing and its sinking, and from the second round on takes the share of a
  // round that balances its work with the others' (detail::balanced_root_share): the samples
  // are the same whoever computes them.
  DriveOutcome run_distributed() {
    using Clock = std::chrono::steady_clock;
    const auto seconds = [](Clock::duration d) { return std::chrono::duration<double>(d).count(); };
    double root_share = 1.0 / ranks_, compute_s = 0.0, sink_s = 0.0;
    std::size_t computed = 0, sunk = 0;
    const auto me = static_cast<std::size_t>(sampling::Cluster::rank());
    Computed mine, theirs;
    for (std::size_t base = spec_.first; base < spec_.total;) {
      const std::size_t chunks_left = (spec_.total - base + chunk_ - 1) / chunk_;
      const std::size_t chunks =
          std::min(detail::kChunksPerRankInARound * static_cast<std::size_t>(ranks_), chunks_left);
      const std::vector<detail::Portion> portions =
          detail::round_portions(base, spec_.total, chunk_, chunks, ranks_, root_share);
      const detail::Portion my = portions[me];
      const Clock::time_point t0 = Clock::now();
      if (my.n > 0) arena_.execute([&] { compute_portion(my.start, my.n, mine); });
      compute_s += seconds(Clock::now() - t0);
      computed += my.n;
      // Rank 0 takes its own portion as it is; every other rank sends its portion chunk by
      // chunk (rank 0 holds one chunk of another rank's at a time).
      std::vector<std::string> messages;
      for (std::size_t from = 0; !root_ && from < my.n; from += chunk_) {
        ByteWriter w;
        const std::size_t n = std::min(chunk_, my.n - from);
        w.put(n);
        for (std::size_t k = from; k < from + n; ++k) encode_(mine.results[k], w);
        w.put_string(mine.prepared[from / chunk_]);
        messages.push_back(std::move(w.bytes()));
      }
      if (root_) {
        const Clock::time_point t1 = Clock::now();
        take(my.start, std::span<const Result>(mine.results.data(), my.n), mine.prepared);
        sink_s += seconds(Clock::now() - t1);
        sunk += my.n;
      }
      std::vector<std::size_t> next_of(portions.size());  // the next chunk's first sample, per rank
      for (std::size_t q = 0; q < portions.size(); ++q) next_of[q] = portions[q].start;
      sampling::Cluster::gather_each(messages, [&](int q, std::string_view bytes) {
        const Clock::time_point t1 = Clock::now();
        ByteReader rd(bytes);
        theirs.results.resize(rd.get<std::size_t>());
        for (auto& r : theirs.results) decode_(rd, r);
        theirs.prepared.resize(1);
        rd.get_string(theirs.prepared[0]);
        std::size_t& at = next_of[static_cast<std::size_t>(q)];
        take(at, theirs.results, theirs.prepared);
        at += theirs.results.size();
        sink_s += seconds(Clock::now() - t1);
        sunk += theirs.results.size();
      });
      base = portions.back().start + portions.back().n;
      if (root_ && computed > 0 && sunk > 0) {
        root_share = detail::balanced_root_share(compute_s / static_cast<double>(computed),
                                                 sink_s / static_cast<double>(sunk), ranks_);
      }
      root_share = sampling::Cluster::broadcast(root_share);
      if (round_ends()) break;
    }
    return out_;
  }

  const DriveSpec spec_;
  Compute compute_;
  Prepare prepare_;
  Sink sink_;
  Stop stop_;
  Encode encode_;
  Decode decode_;
  sampling::Progress* progress_;
  const int ranks_;
  const bool root_;
  const std::size_t chunk_;
  tbb::task_arena arena_;
  tbb::enumerable_thread_specific<Workspace> workspaces_;
  const std::size_t inject_;
  DriveOutcome out_;
  bool stop_now_ = false;
};

/// Runs samples [spec.first, spec.total) through a SampleDriver (see there for the callables).
template <class Result, class MakeWorkspace, class Compute, class Prepare, class Sink, class Stop, class Encode,
          class Decode>
DriveOutcome drive_samples(const DriveSpec& spec, MakeWorkspace make_workspace, Compute compute, Prepare prepare,
                           Sink sink, Stop stop, Encode encode, Decode decode, sampling::Progress* progress = nullptr) {
  SampleDriver<Result, MakeWorkspace, Compute, Prepare, Sink, Stop, Encode, Decode> driver(
      spec, std::move(make_workspace), std::move(compute), std::move(prepare), std::move(sink), std::move(stop),
      std::move(encode), std::move(decode), progress);
  return driver.run();
}

}  // namespace poise::engine
