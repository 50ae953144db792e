#include "engine/results/fault_injection.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <thread>

#include "sampling/interrupt.h"

namespace poise::engine::fault_injection {
namespace {

struct WriteBudget {
  std::mutex mutex;
  std::optional<std::size_t> left;  // bytes still allowed; nullopt: off
  std::string only_file;
};

WriteBudget& write_budget() {
  static WriteBudget b;
  return b;
}

std::atomic<std::size_t> sample_period{0};
constexpr std::size_t kNoHeldSample = static_cast<std::size_t>(-1);
std::atomic<std::size_t> held_sample{kNoHeldSample};
std::atomic<bool> held_reached{false}, held_released{false};

}  // namespace

void fail_writes_after(std::optional<std::size_t> bytes, const std::string& only_file) {
  WriteBudget& b = write_budget();
  const std::lock_guard<std::mutex> lock(b.mutex);
  b.left = bytes;
  b.only_file = only_file;
}

std::size_t allowed_write(const std::string& path, std::size_t n) {
  WriteBudget& b = write_budget();
  const std::lock_guard<std::mutex> lock(b.mutex);
  if (!b.left) return n;
  if (!b.only_file.empty()) {
    const std::string name = std::filesystem::path(path).filename().string();
    if (name != b.only_file && name != b.only_file + ".tmp") return n;
  }
  const std::size_t take = std::min(*b.left, n);
  *b.left -= take;
  return take;
}

void fail_every_sample(std::size_t k) { sample_period.store(k); }

std::size_t failing_sample_period() { return sample_period.load(); }

void hold_at_sample(std::optional<std::size_t> k) {
  held_reached.store(false);
  held_released.store(false);
  held_sample.store(k.value_or(kNoHeldSample));
}

void hold_if_held(std::size_t index) { hold_if_held_in(index, index + 1); }

void hold_if_held_in(std::size_t first, std::size_t last) {
  const std::size_t held = held_sample.load(std::memory_order_relaxed);
  if (held < first || held >= last) return;
  std::fprintf(
      stderr,
      "poise: test hook: sample %zu held until SIGINT or SIGTERM, or its release (POISE_INJECT_HOLD_AT_SAMPLE)\n",
      held);
  std::fflush(stderr);
  held_reached.store(true);
  while (!sampling::interrupt_requested() && !held_released.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

bool hold_reached() { return held_reached.load(); }

void release_hold() { held_released.store(true); }

void set_from_environment() {
  if (const char* after = std::getenv("POISE_INJECT_WRITE_FAILURE_AFTER"); after && *after) {
    const char* only = std::getenv("POISE_INJECT_WRITE_FAILURE_FILE");
    fail_writes_after(static_cast<std::size_t>(std::strtoull(after, nullptr, 10)), only ? only : "");
  }
  if (const char* every = std::getenv("POISE_INJECT_FAILURE_EVERY"); every && *every) {
    fail_every_sample(static_cast<std::size_t>(std::strtoull(every, nullptr, 10)));
  }
  if (const char* hold = std::getenv("POISE_INJECT_HOLD_AT_SAMPLE"); hold && *hold) {
    hold_at_sample(static_cast<std::size_t>(std::strtoull(hold, nullptr, 10)));
  }
}

}  // namespace poise::engine::fault_injection
