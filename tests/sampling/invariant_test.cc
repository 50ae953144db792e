// Internal invariants read apart from user errors (issue 32): POISE_INVARIANT names the broken
// invariant, where it is checked and that it is Poise's bug; require() stays a plain Error.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/error.h"
#include "sampling/statistics.h"

namespace poise {
namespace {

TEST(Invariant, ABrokenInvariantSaysItIsABugAndWhere) {
  const int rows = 3, columns = 4;
  try {
    POISE_INVARIANT(rows == columns, "a square matrix");
    FAIL() << "no throw";
  } catch (const InvariantError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("internal error (a bug in Poise, not in your files"), std::string::npos) << m;
    EXPECT_NE(m.find("invariant 'rows == columns'"), std::string::npos) << m;
    EXPECT_NE(m.find("invariant_test.cc:"), std::string::npos) << m;
    EXPECT_NE(m.find("a square matrix"), std::string::npos) << m;
  }
  EXPECT_NO_THROW(POISE_INVARIANT(rows < columns, "fewer rows"));
}

TEST(Invariant, AUserCheckIsNoInvariant) {
  try {
    require(false, "the density must be positive");
    FAIL() << "no throw";
  } catch (const InvariantError&) {
    FAIL() << "require() must not read as a bug";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "the density must be positive");
  }
}

TEST(Invariant, LibraryPreconditionsAreInvariants) {
  std::vector<double> empty;
  EXPECT_THROW(sampling::quantile_sorted(empty, 0.5), InvariantError);
}

}  // namespace
}  // namespace poise
