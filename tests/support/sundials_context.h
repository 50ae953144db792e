#pragma once
// A SUNDIALS context for a test's own vectors, matrices and solvers, freed at scope end.
#include <sundials/sundials_context.h>

namespace poise::test {

struct SundialsContext {
  SundialsContext() { SUNContext_Create(nullptr, &ctx); }
  ~SundialsContext() { SUNContext_Free(&ctx); }
  SundialsContext(const SundialsContext&) = delete;
  SundialsContext& operator=(const SundialsContext&) = delete;
  SUNContext ctx = nullptr;
};

}  // namespace poise::test
