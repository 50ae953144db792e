#include "sampling/interrupt.h"

#include <csignal>

namespace poise::sampling {
namespace {

std::atomic<int> g_signal{0};
std::atomic<int> g_guards{0};

extern "C" void on_signal(int sig) {
  if (g_signal.exchange(sig) != 0) {
    // Second signal: the default action (terminate) now.
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
}

}  // namespace

InterruptGuard::InterruptGuard() {
  if (g_guards.fetch_add(1) == 0) {
    g_signal.store(0);  // a run that follows a stopped one in the same process (Python, tests) starts afresh
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
  }
}

InterruptGuard::~InterruptGuard() {
  if (g_guards.fetch_sub(1) == 1) {
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
  }
}

bool interrupt_requested() { return g_signal.load() != 0; }
int interrupt_signal() { return g_signal.load(); }

}  // namespace poise::sampling
