// The diagnostics sink (core/diagnostics.h): warnings and progress lines go where the caller
// directs them, a warning given once per process is said once, a capture restores the
// previous sink, and lines from many threads arrive whole.
#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

#include "core/diagnostics.h"

namespace poise::diagnostics {
namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

TEST(Diagnostics, CaptureCollectsWarningsAndProgressApart) {
  Capture outer;
  {
    Capture c;
    warning("the rotor is denser than lead");
    progress("  sweep x = 1: 64 samples");
    warning_once("said once: diagnostics_test");
    warning_once("said once: diagnostics_test");
    EXPECT_EQ(c.warnings(), "the rotor is denser than lead\nsaid once: diagnostics_test\n");
    EXPECT_EQ(c.progress(), "  sweep x = 1: 64 samples\n");
  }
  // The inner capture restored the outer one, which saw nothing of the inner's lines.
  warning("after");
  EXPECT_EQ(outer.warnings(), "after\n");
  EXPECT_TRUE(outer.progress().empty());
  warning_once("said once: diagnostics_test");  // once per process, also across captures
  EXPECT_EQ(outer.warnings(), "after\n");
}

TEST(Diagnostics, LinesFromManyThreadsArriveWhole) {
  Capture c;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([t] {
      for (int i = 0; i < 200; ++i) warning("thread " + std::to_string(t) + " line");
    });
  }
  for (auto& th : threads) th.join();
  for (int t = 0; t < 4; ++t) EXPECT_EQ(count(c.warnings(), "thread " + std::to_string(t) + " line\n"), 200u);
  EXPECT_EQ(count(c.warnings(), "\n"), 800u);
}

TEST(Diagnostics, AnEmptySinkRestoresStderr) {
  const Sink before = set_sink([](Kind, std::string_view) {});
  EXPECT_FALSE(before);  // stderr was the sink
  const Sink mine = set_sink(Sink());
  EXPECT_TRUE(mine);
  testing::internal::CaptureStderr();
  warning("to stderr");
  progress("  a progress line");
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "poise: warning: to stderr\n  a progress line\n");
}

}  // namespace
}  // namespace poise::diagnostics
