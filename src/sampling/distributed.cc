#include "sampling/distributed.h"

#include <sched.h>

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <thread>

#ifdef POISE_WITH_MPI
#include <mpi.h>
#endif

namespace poise::sampling {
namespace {
bool g_mpi = false;
int g_rank = 0, g_size = 1, g_local = 1;
std::size_t g_counters_used = 0;  // SharedCounters made so far (the same on every rank)
#ifdef POISE_WITH_MPI
MPI_Win g_counters = MPI_WIN_NULL;  // kSharedCounters counts at rank 0, several ranks only
#endif
// The tag of the messages send_to_root sends and receive_each takes on rank 0.
constexpr int kRootMessageTag = 19;

// Where each rank's bytes start in the concatenation of all, and their total.
int offsets_of(const std::vector<int>& sizes, std::vector<int>& offsets) {
  offsets.resize(sizes.size());
  int total = 0;
  for (std::size_t q = 0; q < sizes.size(); ++q) {
    offsets[q] = total;
    total += sizes[q];
  }
  return total;
}

// The concatenation of every rank's bytes cut back into them.
std::vector<std::string> split(const std::string& all, const std::vector<int>& sizes, const std::vector<int>& offsets) {
  std::vector<std::string> out;
  for (std::size_t q = 0; q < sizes.size(); ++q) {
    out.push_back(all.substr(static_cast<std::size_t>(offsets[q]), static_cast<std::size_t>(sizes[q])));
  }
  return out;
}

int env_int(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : fallback;
}
#ifdef POISE_WITH_MPI
// Every rank on this machine (mpirun says so before MPI starts): Open MPI's ob1 messaging over
// shared memory, unless the user chose (OMPI_MCA_pml). Its default first probes the network
// libraries (UCX, libfabric), which takes MPI_Init 0.30 s instead of 0.10 s on the development
// VM; on one machine they would only use shared memory anyway.
void prefer_shared_memory_transport() {
  const int size = env_int("OMPI_COMM_WORLD_SIZE", 0);
  if (size > 0 && env_int("OMPI_COMM_WORLD_LOCAL_SIZE", 0) == size && std::getenv("OMPI_MCA_pml") == nullptr) {
    setenv("OMPI_MCA_pml", "ob1", 0);
  }
}

// SharedCounter's counts, all 0, open to every rank until finalize. Where this MPI offers no
// one-sided window (its failure returned, not fatal, on any rank), no rank uses one.
void open_shared_counters() {
  long long* counts = nullptr;
  const MPI_Aint bytes = g_rank == 0 ? static_cast<MPI_Aint>(kSharedCounters * sizeof(long long)) : 0;
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  const bool made =
      MPI_Win_allocate(bytes, sizeof(long long), MPI_INFO_NULL, MPI_COMM_WORLD, &counts, &g_counters) == MPI_SUCCESS;
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_ARE_FATAL);
  int everywhere = made ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &everywhere, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
  if (everywhere == 0) {
    if (made) MPI_Win_free(&g_counters);
    g_counters = MPI_WIN_NULL;
    return;
  }
  if (g_rank == 0) std::fill(counts, counts + kSharedCounters, 0LL);
  MPI_Barrier(MPI_COMM_WORLD);  // every count is 0 before any rank draws
  MPI_Win_lock_all(0, g_counters);
}
#endif

}  // namespace

void Cluster::init([[maybe_unused]] int* argc, [[maybe_unused]] char*** argv) {
  const bool launched = std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMIX_RANK") || std::getenv("PMI_SIZE");
  if (!launched) return;
#ifdef POISE_WITH_MPI
  prefer_shared_memory_transport();
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  g_mpi = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  MPI_Comm node = MPI_COMM_NULL;
  if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, g_rank, MPI_INFO_NULL, &node) == MPI_SUCCESS &&
      node != MPI_COMM_NULL) {
    MPI_Comm_size(node, &g_local);
    MPI_Comm_free(&node);
  } else {
    g_local = env_int("OMPI_COMM_WORLD_LOCAL_SIZE", g_size);
  }
  if (g_size > 1) open_shared_counters();
#else
  if (env_int("OMPI_COMM_WORLD_SIZE", 1) > 1) {
    throw std::runtime_error(
        "started by mpirun with several ranks, but this poise was built without MPI (install libopenmpi-dev "
        "and rebuild: scripts/build.sh); every rank would run the whole study");
  }
#endif
}

void Cluster::finalize() {
#ifdef POISE_WITH_MPI
  if (g_counters != MPI_WIN_NULL) {
    MPI_Win_unlock_all(g_counters);
    MPI_Win_free(&g_counters);
  }
  if (g_mpi) MPI_Finalize();
  g_mpi = false;
#endif
}

void Cluster::abort(int status) {
#ifdef POISE_WITH_MPI
  if (g_mpi && g_size > 1) MPI_Abort(MPI_COMM_WORLD, status);
#endif
  std::exit(status);
}

int Cluster::rank() { return g_rank; }
int Cluster::size() { return g_size; }
int Cluster::local_size() { return g_local; }

int Cluster::default_threads() {
  const int machine = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  int share = std::max(1, machine / std::max(1, g_local));
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (sched_getaffinity(0, sizeof allowed, &allowed) == 0) share = std::min(share, std::max(1, CPU_COUNT(&allowed)));
  return share;
}

std::vector<std::string> Cluster::gather(const std::string& local) {
  if (g_size == 1) return {local};
#ifdef POISE_WITH_MPI
  int n = static_cast<int>(local.size());
  std::vector<int> sizes(g_rank == 0 ? static_cast<std::size_t>(g_size) : 0);
  MPI_Gather(&n, 1, MPI_INT, sizes.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<int> offsets;
  std::string all(static_cast<std::size_t>(offsets_of(sizes, offsets)), '\0');  // rank 0's; empty elsewhere
  MPI_Gatherv(local.data(), n, MPI_CHAR, all.data(), sizes.data(), offsets.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
  return split(all, sizes, offsets);
#else
  return {local};
#endif
}

std::vector<std::string> Cluster::all_gather(const std::string& local) {
  if (g_size == 1) return {local};
#ifdef POISE_WITH_MPI
  int n = static_cast<int>(local.size());
  std::vector<int> sizes(static_cast<std::size_t>(g_size)), offsets;
  MPI_Allgather(&n, 1, MPI_INT, sizes.data(), 1, MPI_INT, MPI_COMM_WORLD);
  std::string all(static_cast<std::size_t>(offsets_of(sizes, offsets)), '\0');
  MPI_Allgatherv(local.data(), n, MPI_CHAR, all.data(), sizes.data(), offsets.data(), MPI_CHAR, MPI_COMM_WORLD);
  return split(all, sizes, offsets);
#else
  return {local};
#endif
}

void Cluster::receive_each([[maybe_unused]] const std::function<void(int, std::string_view)>& take) {
#ifdef POISE_WITH_MPI
  if (g_size == 1 || g_rank != 0) return;
  std::string buffer;
  for (int q = 1; q < g_size; ++q) {
    long long count = 0;
    MPI_Recv(&count, 1, MPI_LONG_LONG, q, kRootMessageTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    for (long long m = 0; m < count; ++m) {
      long long n = 0;
      MPI_Recv(&n, 1, MPI_LONG_LONG, q, kRootMessageTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      buffer.resize(static_cast<std::size_t>(n));
      MPI_Recv(buffer.data(), static_cast<int>(n), MPI_CHAR, q, kRootMessageTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      take(q, buffer);
    }
  }
#endif
}

struct PendingSends::Impl {
  std::vector<std::string> messages;
  std::vector<long long> header;  // the count, then each message's size
#ifdef POISE_WITH_MPI
  std::vector<MPI_Request> requests;
#endif
};

PendingSends::PendingSends() : impl_(std::make_unique<Impl>()) {}

PendingSends::~PendingSends() {
  try {
    Cluster::wait(*this);
  } catch (...) {  // a destructor does not throw
  }
}

void Cluster::send_to_root([[maybe_unused]] std::vector<std::string> messages, [[maybe_unused]] PendingSends& pending) {
#ifdef POISE_WITH_MPI
  if (g_size == 1 || g_rank == 0) return;
  wait(pending);
  PendingSends::Impl& p = *pending.impl_;
  p.messages = std::move(messages);
  p.header.assign(1, static_cast<long long>(p.messages.size()));
  for (const std::string& m : p.messages) p.header.push_back(static_cast<long long>(m.size()));
  p.requests.assign(1 + 2 * p.messages.size(), MPI_REQUEST_NULL);
  MPI_Isend(p.header.data(), 1, MPI_LONG_LONG, 0, kRootMessageTag, MPI_COMM_WORLD, &p.requests[0]);
  for (std::size_t k = 0; k < p.messages.size(); ++k) {
    MPI_Isend(&p.header[k + 1], 1, MPI_LONG_LONG, 0, kRootMessageTag, MPI_COMM_WORLD, &p.requests[1 + 2 * k]);
    MPI_Isend(p.messages[k].data(), static_cast<int>(p.messages[k].size()), MPI_CHAR, 0, kRootMessageTag,
              MPI_COMM_WORLD, &p.requests[2 + 2 * k]);
  }
#endif
}

void Cluster::wait([[maybe_unused]] PendingSends& pending) {
#ifdef POISE_WITH_MPI
  PendingSends::Impl& p = *pending.impl_;
  if (!p.requests.empty() && g_mpi) {
    MPI_Waitall(static_cast<int>(p.requests.size()), p.requests.data(), MPI_STATUSES_IGNORE);
  }
  p.requests.clear();
  p.messages.clear();
#endif
}

namespace {
constexpr int kFromRootTag = 23;
}  // namespace

void Cluster::send_to([[maybe_unused]] int rank, [[maybe_unused]] std::string_view bytes) {
#ifdef POISE_WITH_MPI
  if (!g_mpi) return;
  const auto n = static_cast<long long>(bytes.size());
  MPI_Send(&n, 1, MPI_LONG_LONG, rank, kFromRootTag, MPI_COMM_WORLD);
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_CHAR, rank, kFromRootTag, MPI_COMM_WORLD);
#endif
}

std::string Cluster::receive_from_root() {
  std::string out;
#ifdef POISE_WITH_MPI
  if (!g_mpi) return out;
  long long n = 0;
  MPI_Recv(&n, 1, MPI_LONG_LONG, 0, kFromRootTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  out.resize(static_cast<std::size_t>(n));
  MPI_Recv(out.data(), static_cast<int>(n), MPI_CHAR, 0, kFromRootTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
#endif
  return out;
}

bool Cluster::any(bool flag) {
  if (g_size == 1) return flag;
#ifdef POISE_WITH_MPI
  int in = flag ? 1 : 0, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
  return out != 0;
#else
  return flag;
#endif
}

std::string Cluster::broadcast(const std::string& value) {
  if (g_size == 1) return value;
#ifdef POISE_WITH_MPI
  long long n = static_cast<long long>(value.size());
  MPI_Bcast(&n, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  std::string out = g_rank == 0 ? value : std::string(static_cast<std::size_t>(n), '\0');
  MPI_Bcast(out.data(), static_cast<int>(n), MPI_CHAR, 0, MPI_COMM_WORLD);
  return out;
#else
  return value;
#endif
}

SharedCounter::SharedCounter() : session_(g_counters_used++), next_(0), step_(1) {
#ifdef POISE_WITH_MPI
  shared_ = g_counters != MPI_WIN_NULL && session_ < kSharedCounters;
#endif
  if (shared_) return;
  // No window, or every counter used: every size-th number, rank 0 the last of each size.
  next_ = static_cast<std::size_t>((g_rank + g_size - 1) % g_size);
  step_ = static_cast<std::size_t>(g_size);
}

std::size_t SharedCounter::next() {
#ifdef POISE_WITH_MPI
  if (shared_) {
    const long long one = 1;
    long long before = 0;
    MPI_Fetch_and_op(&one, &before, MPI_LONG_LONG, 0, static_cast<MPI_Aint>(session_), MPI_SUM, g_counters);
    MPI_Win_flush(0, g_counters);
    return static_cast<std::size_t>(before);
  }
#endif
  const std::size_t n = next_;
  next_ += step_;
  return n;
}

}  // namespace poise::sampling
