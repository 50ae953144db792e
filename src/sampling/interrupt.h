#pragma once
/// Clean stops on SIGINT and SIGTERM. While an InterruptGuard lives, the first signal only
/// sets a flag that the run loops poll between blocks: the block in flight finishes, is
/// written, and the run ends with a summary of what was done (`poise run --resume` completes
/// it). A second signal of the same kind ends the process at once; the samples already
/// written are kept either way (results stream to disk block by block), as under kill -9.
/// The outermost guard starts with no stop requested: a run that follows a stopped one in the
/// same process (the Python module, a test) is not stopped by the earlier signal.
#include <atomic>

namespace poise::sampling {

class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
};

/// True once SIGINT or SIGTERM arrived under a guard (or request_interrupt was called).
bool interrupt_requested();
/// The signal that asked for the stop (0 if none).
int interrupt_signal();

}  // namespace poise::sampling
