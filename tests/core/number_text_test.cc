// core/number_text: a statistic and its interval written at the decimal place the interval
// supports (issue 33: one number formatter).
#include <gtest/gtest.h>

#include <cmath>

#include "core/number_text.h"

namespace poise {
namespace {

void expect_text(double v, std::optional<double> lo, std::optional<double> hi, const char* want_v, const char* want_lo,
                 const char* want_hi) {
  const IntervalText t = interval_text(v, lo, hi);
  EXPECT_EQ(t.value, want_v);
  EXPECT_EQ(t.lo, want_lo);
  EXPECT_EQ(t.hi, want_hi);
}

TEST(NumberText, DigitsFollowTheIntervalsWidth) {
  expect_text(9.0, 8.911, 9.089, "9.000", "8.911", "9.089");      // not "9 [8.911, 9.089]"
  expect_text(1.1315, 1.0127, 1.2333, "1.13", "1.01", "1.23");    // half-width 0.1: two digits of it
  expect_text(20.684, 20.312, 21.031, "20.68", "20.31", "21.03");
  expect_text(12345.6, 12000.0, 12700.0, "12346", "12000", "12700");  // no decimals beyond 10
  expect_text(0.000123456, 0.000120001, 0.000127, "0.0001235", "0.0001200", "0.0001270");
}

TEST(NumberText, OneSidedAndDegenerateIntervals) {
  expect_text(5.0, std::nullopt, 7.0, "5.0", "", "7.0");
  expect_text(1.0, 1.0, 1.0, "1", "1", "1");                  // zero width: 4 significant digits
  expect_text(-1.0e-16, -2.0e-3, 2.0e-3, "0.0000", "-0.0020", "0.0020");  // floating noise reads as 0
  expect_text(NAN, 1.0, 2.0, "nan", "1", "2");
}

TEST(NumberText, NeverMoreThanSevenSignificantDigits) {
  const IntervalText t = interval_text(123456.789, 123456.7, 123456.9);
  EXPECT_EQ(t.value, "123456.8");
  EXPECT_EQ(t.lo, "123456.7");
}

}  // namespace
}  // namespace poise
