#include "engine/kind_interface/programs_allowed.h"

#include <atomic>

namespace poise::engine {
namespace {
std::atomic<bool> g_allowed{false};
}  // namespace

bool programs_allowed() { return g_allowed.load(); }
void allow_programs(bool allowed) { g_allowed.store(allowed); }

}  // namespace poise::engine
