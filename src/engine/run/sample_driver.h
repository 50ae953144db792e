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
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/error.h"
#include "engine/results/fault_injection.h"
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

/// Bytes of a result, for the trip from a rank to rank 0 (plain fields only).
class ByteWriter {
 public:
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    out_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <class T>
  void put_vector(const std::vector<T>& v) {
    put(v.size());
    out_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void put_string(const std::string& s) {
    put(s.size());
    out_.append(s);
  }
  std::string& bytes() { return out_; }

 private:
  std::string out_;
};

class ByteReader {
 public:
  explicit ByteReader(std::string_view in) : in_(in) {}
  template <class T>
  T get() {
    T v;
    take(&v, sizeof v);
    return v;
  }
  template <class T>
  void get_vector(std::vector<T>& v) {
    v.resize(get<std::size_t>());
    take(v.data(), v.size() * sizeof(T));
  }
  void get_string(std::string& s) {
    s.resize(get<std::size_t>());
    take(s.data(), s.size());
  }
  bool done() const { return pos_ == in_.size(); }

 private:
  void take(void* dst, std::size_t n) {
    require(pos_ + n <= in_.size(), "corrupt sample message from an MPI rank");
    if (n > 0) std::memcpy(dst, in_.data() + pos_, n);
    pos_ += n;
  }
  std::string_view in_;
  std::size_t pos_ = 0;
};

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

/// Runs the samples. compute(i, workspace, result); sink(first_index, span of results) on
/// rank 0 in order; stop(completed) on rank 0 after each chunk, returning a reason to stop
/// ("" to go on); encode(result, ByteWriter&) and decode(ByteReader&, result) carry results
/// between ranks. Rank 0's outcome is every rank's.
template <class Result, class MakeWorkspace, class Compute, class Sink, class Stop, class Encode, class Decode>
DriveOutcome drive_samples(const DriveSpec& spec, MakeWorkspace make_workspace, Compute compute, Sink sink, Stop stop,
                           Encode encode, Decode decode, sampling::Progress* progress = nullptr) {
  using Workspace = decltype(make_workspace());
  const int ranks = spec.distributed ? sampling::Cluster::size() : 1;
  const int me = spec.distributed ? sampling::Cluster::rank() : 0;
  const bool root = me == 0;
  tbb::task_arena arena(std::max(1, spec.threads));
  tbb::enumerable_thread_specific<Workspace> workspaces(make_workspace);
  const std::size_t chunk = std::max<std::size_t>(spec.chunk, 1);
  std::vector<Result> local(std::min(chunk, std::max<std::size_t>(spec.total - std::min(spec.first, spec.total), 1)));
  DriveOutcome out;
  out.completed = spec.first;
  const std::size_t round_size = chunk * static_cast<std::size_t>(ranks);
  // Fault injection for the tests of failure handling (engine/results/fault_injection.h):
  // every k-th sample (indices k-1, 2k-1, ...) fails as a solver failure would.
  const std::size_t inject = fault_injection::failing_sample_period();
  auto compute_chunk = [&](std::size_t first, std::size_t n, std::vector<Result>& into) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, std::max<std::size_t>(spec.grain, 1)),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        Workspace& ws = workspaces.local();
                        for (std::size_t k = r.begin(); k != r.end(); ++k) {
                          compute(first + k, ws, into[k]);
                          if (inject > 0 && (first + k + 1) % inject == 0) {
                            into[k].ok = false;
                            into[k].message = "injected failure (fault_injection::fail_every_sample)";
                          }
                        }
                      });
  };
  // One process: the next chunk is computed on the arena's other threads while this one is
  // sunk (written, counted, checked by the stop rule) on the calling thread, so that the
  // writing does not leave the cores idle. A chunk computed past a stop point is not kept.
  std::vector<Result> ahead_results;
  tbb::task_group ahead;
  bool computed_ahead = false;
  for (std::size_t base = spec.first; base < spec.total; base += round_size) {
    const std::size_t my_start = std::min(base + static_cast<std::size_t>(me) * chunk, spec.total);
    const std::size_t my_n = std::min(chunk, spec.total - my_start);
    if (!computed_ahead) arena.execute([&] { compute_chunk(my_start, my_n, local); });
    computed_ahead = false;
    bool stop_now = false;
    auto take_chunk = [&](std::size_t start, std::span<const Result> results) {
      if (stop_now || results.empty()) return;  // past a stop point: computed, not kept
      sink(start, results);
      out.completed = start + results.size();
      out.stop_reason = stop(out.completed);
      stop_now = !out.stop_reason.empty();
      if (progress) progress->update(out.completed - spec.first);
    };
    if (ranks == 1) {
      const std::size_t next = base + round_size;
      const bool pipelined = next < spec.total;
      if (pipelined) {
        ahead_results.resize(local.size());
        arena.execute(
            [&] { ahead.run([&, next] { compute_chunk(next, std::min(chunk, spec.total - next), ahead_results); }); });
      }
      try {
        take_chunk(my_start, std::span<const Result>(local.data(), my_n));
      } catch (...) {
        if (pipelined) arena.execute([&] { ahead.wait(); });  // its buffers go out of scope
        throw;
      }
      if (pipelined) {
        arena.execute([&] { ahead.wait(); });
        std::swap(local, ahead_results);
        computed_ahead = true;
      }
    } else {
      ByteWriter w;
      w.put(my_n);
      for (std::size_t k = 0; k < my_n; ++k) encode(local[k], w);
      // Rank by rank: rank 0 decodes and sinks one rank's chunk before it receives the next.
      std::vector<Result> theirs;
      sampling::Cluster::gather_each(w.bytes(), [&](int q, std::string_view bytes) {
        ByteReader rd(bytes);
        theirs.resize(rd.get<std::size_t>());
        for (auto& r : theirs) decode(rd, r);
        take_chunk(std::min(base + static_cast<std::size_t>(q) * chunk, spec.total), theirs);
      });
    }
    if (root && sampling::interrupt_requested()) {
      out.interrupted = true;
      out.signal = sampling::interrupt_signal();
    }
    // Every rank learns rank 0's decision (and any rank's signal).
    const bool any_signal = ranks > 1 ? sampling::Cluster::any(sampling::interrupt_requested()) : false;
    const bool end =
        ranks > 1 ? sampling::Cluster::any(root && (stop_now || out.interrupted)) : (stop_now || out.interrupted);
    if (any_signal && root && !out.interrupted && !stop_now) {
      out.interrupted = true;
      out.signal = 15;
    }
    if (end || (any_signal && ranks > 1)) break;
  }
  return out;
}

}  // namespace poise::engine
