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
#include <atomic>
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

/// How many samples this process has computed: every sample the loop below computes, and any a
/// study recomputes itself (it adds them). A resumed run computes only the samples it lacks,
/// which the resume tests check by this count (tests/kinds/resume_computes_test.cc).
inline std::atomic<std::size_t>& samples_computed() {
  static std::atomic<std::size_t> count{0};
  return count;
}

/// The fields every sample result has that rank 0 reads (index, ok, message, outputs), for the
/// encode/decode of a result type. Not the inputs: only samples.csv's rows show them, and they
/// are formatted where the sample was computed (a fifth of a LOS sample's bytes).
template <class Result>
void encode_sample_fields(const Result& r, ByteWriter& w) {
  w.put(r.index);
  w.put(r.ok);
  w.put_string(r.message);
  w.put_vector(r.outputs);
}
template <class Result>
void decode_sample_fields(ByteReader& rd, Result& r) {
  r.index = rd.get<std::size_t>();
  r.ok = rd.get<bool>();
  rd.get_string(r.message);
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

/// Rank 0's share of a round's chunks that gives it as much work as each other rank: rank 0
/// computes (and formats) a sample in `root_compute` seconds and, meanwhile, takes `root_sink`
/// for every sample of the round before (receiving, writing), `sunk_per_computed` of them per
/// sample of this round; the other ranks take `other_compute` per sample they compute
/// (computing, formatting, encoding). With R ranks, N samples and M = N x sunk_per_computed
/// sunk, rank 0's n0 c0 + M s equals each other rank's (N - n0) / (R - 1) c: n0 / N =
/// (c / (R - 1) - s M / N) / (c0 + c / (R - 1)); none when that is negative. Even shares until
/// both are measured.
inline double balanced_root_share(double root_compute, double root_sink, double other_compute, int ranks,
                                  double sunk_per_computed = 1.0) {
  if (!(root_compute > 0.0) || !(other_compute > 0.0)) return 1.0 / ranks;
  const double other = other_compute / (ranks - 1);
  return std::clamp((other - root_sink * sunk_per_computed) / (root_compute + other), 0.0, 1.0);
}

/// Chunks per rank in a round of an MPI run. The first rounds run before the timings balance
/// rank 0's share, and the last round's writing on rank 0 has nothing beside it on the other
/// ranks, so both are short: one chunk per rank for the first two, then a quarter of the chunks
/// left (spread over the ranks), at most kChunksPerRankInARound, so that the few blocking
/// exchanges of a round (its end, the timings) stay rare in a long run. Towards the end each
/// round is 3/4 of the one before: rank 0 writes the one before while the others compute it,
/// which balances while writing a sample takes no more than 3/4 of computing one.
inline constexpr std::size_t kChunksPerRankInARound = 8;
inline constexpr std::size_t kShortFirstRounds = 2;
inline std::size_t chunks_per_rank(std::size_t round, std::size_t chunks_left, int ranks) {
  if (round < kShortFirstRounds) return 1;
  const std::size_t quarter = chunks_left / (4 * static_cast<std::size_t>(std::max(ranks, 1)));
  return std::clamp<std::size_t>(quarter, 1, kChunksPerRankInARound);
}

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
  // (indices k-1, 2k-1, ...) fails as a solver failure would; a held sample waits for a signal.
  void compute_portion(std::size_t first, std::size_t n, Computed& into) {
    if (into.results.size() < n) into.results.resize(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, std::max<std::size_t>(spec_.grain, 1)),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        Workspace& ws = workspaces_.local();
                        // A study that computes its samples in batches gets the task's range first.
                        if constexpr (requires { ws->begin_range(std::size_t{}, std::size_t{}); }) {
                          ws->begin_range(first + r.begin(), r.size());
                        }
                        samples_computed().fetch_add(r.size(), std::memory_order_relaxed);
                        for (std::size_t k = r.begin(); k != r.end(); ++k) {
                          fault_injection::hold_if_held(first + k);
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

  // Several ranks: rounds of chunks (detail::chunks_per_rank), each rank computing its portion.
  // Between two exchanges every rank works on the same two rounds: rank 0 sinks a round's
  // portions in rank order, its own first, then the others' as they arrive, chunk by chunk (one
  // chunk of another rank's in memory at a time), and computes its portion of the following
  // round; the other ranks send their portions of the round and compute theirs of the following
  // one. So rank 0's writing overlaps their computing, also when rounds change in size. Rank 0's
  // decision on a round (stop, a signal) reaches them as they finish the following one, which
  // is then dropped. Every rank times its work, and from the ranks' timings rank 0's share of
  // the round after the following one balances its work with the others'
  // (detail::balanced_root_share); the samples are the same whoever computes them.
  DriveOutcome run_distributed() {
    using Clock = std::chrono::steady_clock;
    const auto seconds = [](Clock::duration d) { return std::chrono::duration<double>(d).count(); };
    const auto me = static_cast<std::size_t>(sampling::Cluster::rank());
    Timing timing;
    std::size_t round_index = 0;
    std::vector<detail::Portion> round = next_round(spec_.first, round_index++, timing, 0);
    Computed mine, ahead;
    sampling::PendingSends sending;
    compute_portion(round[me], mine);  // not timed: it includes the workspaces' start
    while (!round.empty()) {
      const std::size_t end_of_round = round.back().start + round.back().n;
      const std::size_t round_n = end_of_round - round.front().start;
      std::vector<detail::Portion> following = next_round(end_of_round, round_index++, timing, round_n);
      const Clock::time_point t1 = Clock::now();
      if (root_) {
        timing.add_sink(sink_round(round, mine), round_n);
      } else {
        sampling::Cluster::send_to_root(encode_portion(round[me], mine), sending);
      }
      const Clock::time_point t2 = Clock::now();
      if (!following.empty()) compute_portion(following[me], ahead);
      const double computing = seconds(Clock::now() - (root_ ? t2 : t1));  // the others' includes sending
      if (!following.empty()) timing.add_compute(computing, following[me].n);
      // Rank 0's decision on this round, and the timings for the share of the round after the following one.
      const bool end = round_ends();
      timing.exchange(ranks_);
      if (end) break;
      sampling::Cluster::wait(sending);  // the round's messages are rank 0's: their buffers free
      std::swap(mine, ahead);
      round = std::move(following);
    }
    sampling::Cluster::wait(sending);
    return out_;
  }

  // A rank's busy seconds: computing (with formatting and, on the other ranks, encoding and
  // sending) and, on rank 0, sinking; and their samples, each round's weighing half as much at
  // every exchange, so that the share follows a cost that changes along the run yet a round
  // with a lumpy cost (samples.h5 compresses a whole chunk of rows at once) does not swing it.
  // exchange() shares every rank's figures per sample (the same on every rank, so the same
  // share everywhere).
  struct Timing {
    double compute_s = 0.0, sink_s = 0.0;
    double computed = 0.0, sunk = 0.0;                         // samples (weighted as the seconds)
    double root_compute = 0.0, root_sink = 0.0, others = 0.0;  // per sample, as last exchanged
    double my_compute = 0.0, my_sink = 0.0;                    // this rank's, as last sent
    bool exchanged = false;
    void add_compute(double s, std::size_t n) {
      compute_s += s;
      computed += static_cast<double>(n);
    }
    void add_sink(double s, std::size_t n) {
      sink_s += s;
      sunk += static_cast<double>(n);
    }
    static double per_sample(double s, double n, double before) { return n > 0.0 ? s / n : before; }
    void exchange(int ranks) {
      my_compute = per_sample(compute_s, computed, my_compute);
      my_sink = per_sample(sink_s, sunk, my_sink);
      compute_s *= 0.5, sink_s *= 0.5;
      computed *= 0.5, sunk *= 0.5;
      ByteWriter w;
      w.put(my_compute);
      w.put(my_sink);
      const std::vector<std::string> all = sampling::Cluster::all_gather(w.bytes());
      others = 0.0;
      bool measured = ranks > 1;
      for (std::size_t q = 1; q < all.size(); ++q) {
        ByteReader rd(all[q]);
        const double c = rd.get<double>();
        measured = measured && c > 0.0;
        others += c / static_cast<double>(all.size() - 1);
      }
      ByteReader root(all[0]);
      root_compute = root.get<double>();
      root_sink = root.get<double>();
      exchanged = measured;  // else even shares until every rank has computed
    }
    // Rank 0's share of a round of `computed_n` samples computed beside `sunk_n` sunk; never more
    // than an even one, so that rank 0's memory (its portions) does not grow with the rank count
    // when the others are slower (several ranks on a core).
    double share(int ranks, std::size_t sunk_n, std::size_t computed_n) const {
      if (!exchanged || computed_n == 0) return 1.0 / ranks;
      return std::min(1.0 / ranks,
                      detail::balanced_root_share(root_compute, root_sink, others, ranks,
                                                  static_cast<double>(sunk_n) / static_cast<double>(computed_n)));
    }
  };

  // The portions of the `index`-th round (from 0), from `base` (none past the end), computed
  // beside the sinking of `sunk_n` samples on rank 0.
  std::vector<detail::Portion> next_round(std::size_t base, std::size_t index, const Timing& timing,
                                          std::size_t sunk_n) const {
    if (base >= spec_.total) return {};
    const std::size_t chunks_left = (spec_.total - base + chunk_ - 1) / chunk_;
    const std::size_t chunks =
        std::min(detail::chunks_per_rank(index, chunks_left, ranks_) * static_cast<std::size_t>(ranks_), chunks_left);
    const std::size_t n = std::min(spec_.total - base, chunks * chunk_);
    return detail::round_portions(base, spec_.total, chunk_, chunks, ranks_, timing.share(ranks_, sunk_n, n));
  }

  void compute_portion(const detail::Portion& p, Computed& into) {
    if (p.n > 0) arena_.execute([&] { compute_portion(p.start, p.n, into); });
  }

  // A portion's messages to rank 0, one per chunk: its results and prepared bytes.
  std::vector<std::string> encode_portion(const detail::Portion& p, const Computed& c) {
    std::vector<std::string> messages;
    for (std::size_t from = 0; from < p.n; from += chunk_) {
      ByteWriter w;
      const std::size_t n = std::min(chunk_, p.n - from);
      w.put(n);
      for (std::size_t k = from; k < from + n; ++k) encode_(c.results[k], w);
      w.put_string(c.prepared[from / chunk_]);
      messages.push_back(std::move(w.bytes()));
    }
    return messages;
  }

  // Rank 0: the round's portions sunk in order, its own as computed, the others' as received.
  // Returns the seconds it took, receiving included (the others sent their portions before
  // computing on, so it is rank 0's work, not waiting).
  double sink_round(const std::vector<detail::Portion>& round, const Computed& own) {
    using Clock = std::chrono::steady_clock;
    const Clock::time_point t0 = Clock::now();
    take(round[0].start, std::span<const Result>(own.results.data(), round[0].n), own.prepared);
    std::vector<std::size_t> next_of(round.size());  // the next chunk's first sample, per rank
    for (std::size_t q = 0; q < round.size(); ++q) next_of[q] = round[q].start;
    Computed theirs;
    sampling::Cluster::receive_each([&](int q, std::string_view bytes) {
      ByteReader rd(bytes);
      theirs.results.resize(rd.get<std::size_t>());
      for (auto& r : theirs.results) decode_(rd, r);
      theirs.prepared.resize(1);
      rd.get_string(theirs.prepared[0]);
      std::size_t& at = next_of[static_cast<std::size_t>(q)];
      take(at, theirs.results, theirs.prepared);
      at += theirs.results.size();
    });
    return std::chrono::duration<double>(Clock::now() - t0).count();
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
