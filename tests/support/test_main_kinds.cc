// The main of the tests of the study kinds and above: the kinds are registered with the engine
// (as the CLI does), then GoogleTest runs.
#include <gtest/gtest.h>

#include "kinds/registry.h"

int main(int argc, char** argv) {
  poise::kinds::register_study_kinds();
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
