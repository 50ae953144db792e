#pragma once
/// The processes of a run. Built with Open MPI (POISE_WITH_MPI) and started by mpirun,
/// `poise run` splits its samples over the ranks: round by round, each rank computes a
/// contiguous portion of the round's chunks of the sample order on its own threads (rank 0 a
/// smaller one when writing the results takes its time: engine/run/sample_driver.h), and rank
/// 0 gathers them, writes them in order and makes every decision (stop at a target interval,
/// too many failures, a signal), which all ranks then share. Every sample depends only on
/// (seed, index), so the samples and statistics equal a one-process run's. Without MPI, or
/// when not started by mpirun, there is one rank and every call is trivial.
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace poise::sampling {

/// Messages on their way from a rank to rank 0 (Cluster::send_to_root): they stay here until
/// Cluster::wait says rank 0 has them (the destructor waits too).
class PendingSends {
 public:
  PendingSends();
  ~PendingSends();
  PendingSends(const PendingSends&) = delete;
  PendingSends& operator=(const PendingSends&) = delete;

 private:
  friend class Cluster;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A count every rank draws from: next() hands out 0, 1, 2, ... each number to one rank,
/// whichever asks first, without the others taking part (MPI's passive-target fetch-and-add on
/// a window Cluster::init makes at rank 0; through shared memory on one machine; across
/// machines a draw may wait until rank 0 next calls MPI). Every rank makes the same sequence of
/// SharedCounters (the n-th one on each rank is the same count) and is not made to wait by
/// making one. Each draws until it gets a number past what it needs. Past kSharedCounters
/// counts in a process, or without a window: rank r gets r - 1, r - 1 + size, ... (rank 0 the
/// last of each size).
inline constexpr std::size_t kSharedCounters = 64;
class SharedCounter {
 public:
  SharedCounter();
  std::size_t next();

 private:
  std::size_t session_, next_, step_;
  bool shared_ = false;  ///< drawn from the window; else next_, next_ + step_, ...
};

class Cluster {
 public:
  /// Starts MPI when built with it and launched by mpirun (OMPI_COMM_WORLD_SIZE or
  /// PMIX_RANK set); a no-op otherwise. Call once, from main, before any other use.
  static void init(int* argc, char*** argv);
  static void finalize();
  /// Ends every rank (after an error on one of them), with this exit status.
  [[noreturn]] static void abort(int status);
  static int rank();
  static int size();
  static bool root() { return rank() == 0; }
  /// Ranks on this machine (to share its cores between them): MPI's shared-memory split of
  /// the ranks, so it holds under mpirun and under a batch system's launcher (srun) alike.
  static int local_size();
  /// The threads a run uses when none are asked for: the cores this process may run on (its
  /// CPU affinity, which mpirun's binding and a batch system's allocation, e.g. SLURM's
  /// --cpus-per-task, set), and no more than this machine's cores shared among its ranks.
  static int default_threads();
  /// Each rank's bytes, gathered at rank 0 in rank order; other ranks get an empty vector.
  static std::vector<std::string> gather(const std::string& local);
  /// Each rank's bytes, on every rank, in rank order.
  static std::vector<std::string> all_gather(const std::string& local);
  /// On rank 0: every other rank's messages (send_to_root) handed to `take(rank, bytes)`, one rank
  /// at a time in rank order, each rank's in their order: rank 0 holds one message at a time, so
  /// its memory grows neither with the number of ranks nor with that of their messages.
  static void receive_each(const std::function<void(int, std::string_view)>& take);
  /// On a rank other than 0: sends its messages to rank 0, as receive_each takes them there,
  /// without waiting for rank 0 to take them (the rank computes on meanwhile); `pending` keeps
  /// them until wait(pending). A rank sends one set at a time: wait before the next.
  static void send_to_root(std::vector<std::string> messages, PendingSends& pending);
  static void wait(PendingSends& pending);
  /// Rank 0 to one rank: `send_to(rank, bytes)` on rank 0 returns once that rank has them,
  /// which it takes by `receive_from_root()`, in the order sent.
  static void send_to(int rank, std::string_view bytes);
  static std::string receive_from_root();
  /// Logical OR of every rank's flag, on every rank.
  static bool any(bool flag);
  /// Rank 0's bytes, on every rank.
  static std::string broadcast(const std::string& value);
};

}  // namespace poise::sampling
