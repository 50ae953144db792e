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

void hold_at_sample(std::optional<std::size_t> k) { held_sample.store(k.value_or(kNoHeldSample)); }

void hold_if_held(std::size_t index) {
  if (index != held_sample.load(std::memory_order_relaxed)) return;
  std::fprintf(stderr, "poise: test hook: sample %zu held until SIGINT or SIGTERM (POISE_INJECT_HOLD_AT_SAMPLE)\n",
               index);
  std::fflush(stderr);
  while (!sampling::interrupt_requested()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
}

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
