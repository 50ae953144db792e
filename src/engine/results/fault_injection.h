#pragma once
/// Test hooks for failure handling, set by whoever runs the engine (a test in process, or the
/// command line's entry point from its POISE_INJECT_* variables): the engine itself never
/// reads the environment. Off by default; process-wide and thread-safe.
///   write failures  every checked write of the process (engine/results/checked_file.h) may
///                   pass `bytes` bytes in total, the rest fail as a full disk (ENOSPC);
///                   with `only_file`, only writes to that file name (or its ".tmp") count.
///   sample failures every k-th sample (indices k-1, 2k-1, ...) of a run fails as a solver
///                   failure would (engine/run/sample_driver.h).
///   a held sample   the sample of index k waits, before it is computed, until a stop is
///                   requested (SIGINT or SIGTERM, sampling/interrupt.h), and says so once on
///                   stderr: a run under this hook cannot end before its signal, so a test of
///                   the clean stop does not race the machine (tests/cli/reliability_test.cc).
#include <cstddef>
#include <optional>
#include <string>

namespace poise::engine::fault_injection {

/// Lets `bytes` more bytes through (then ENOSPC); std::nullopt: writes never fail.
void fail_writes_after(std::optional<std::size_t> bytes, const std::string& only_file = "");
/// How many of `n` bytes to `path` the hook lets through (n when off); counts them.
std::size_t allowed_write(const std::string& path, std::size_t n);

/// Every k-th sample fails (0: none).
void fail_every_sample(std::size_t k);
std::size_t failing_sample_period();

/// The sample of index k is held until a stop is requested or release_hold() is called
/// (std::nullopt: none); resets hold_reached().
void hold_at_sample(std::optional<std::size_t> k);
/// Holds the calling thread if `index` is the held sample: returns once a stop is requested or
/// the hold is released (at once when the hook is off or `index` is another sample).
void hold_if_held(std::size_t index);
/// The same for a block of samples [first, last) computed together (evaluate's chunks).
void hold_if_held_in(std::size_t first, std::size_t last);
/// Whether a thread has reached the held sample; and lets it go on (the Python module's test of
/// evaluate releasing the GIL: the test's own thread sees the hold and releases it).
bool hold_reached();
void release_hold();

/// The hooks from POISE_INJECT_WRITE_FAILURE_AFTER, POISE_INJECT_WRITE_FAILURE_FILE,
/// POISE_INJECT_FAILURE_EVERY and POISE_INJECT_HOLD_AT_SAMPLE, for a program's entry point
/// (the `poise` command and the Python module call it once, before they run anything).
void set_from_environment();

}  // namespace poise::engine::fault_injection
