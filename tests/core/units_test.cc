// Tests of the units module (src/core/units.h): parsing "<number> <unit>" strings into
// SI values with dimensions, the error messages for bad input, and formatting.
#include "core/units.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/error.h"

namespace {

using poise::Error;
namespace u = poise::units;

// Independent constants (not taken from units.h).
constexpr double kPi = 3.14159265358979323846;
const double kArcsecPerRadRef = 180.0 * 3600.0 / kPi;  // 206264.80624709636

// Runs f, expects a poise::Error whose message contains every fragment; returns the message.
template <typename F>
std::string expect_error(F&& f, std::initializer_list<std::string> fragments) {
  try {
    f();
  } catch (const Error& e) {
    const std::string msg = e.what();
    for (const auto& frag : fragments) {
      EXPECT_NE(msg.find(frag), std::string::npos) << "message \"" << msg << "\" lacks \"" << frag << "\"";
    }
    return msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw a non-poise exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "did not throw";
  return {};
}

TEST(Units, ConstantsMatchIndependentValues) {
  EXPECT_NEAR(u::kArcsecPerRad, 206264.80624709636, 1e-9);
  EXPECT_NEAR(u::kRadPerArcsec * 206264.80624709636, 1.0, 1e-15);
  EXPECT_NEAR(u::kRadPerDeg, 0.017453292519943295, 1e-18);
}

TEST(Units, LengthMillimetres) {
  // 0.004 mm = 4e-6 m; tolerance: one rounding of the product (1e-15 relative).
  EXPECT_NEAR(u::parse_as("0.004 mm", u::kLength), 4e-6, 4e-6 * 1e-15);
  const u::Quantity q = u::parse_quantity("0.004 mm");
  EXPECT_EQ(q.dim, u::kLength);
  EXPECT_NEAR(u::parse_as("82 mm", u::kLength), 0.082, 1e-17);
  EXPECT_NEAR(u::parse_as("  2.5 um ", u::kLength), 2.5e-6, 1e-21);
  EXPECT_NEAR(u::parse_as("1 km", u::kLength), 1000.0, 1e-12);
}

TEST(Units, Angles) {
  EXPECT_NEAR(u::parse_as("30 deg", u::kAngle), kPi / 6.0, 1e-15);
  // 4 arcsec = 4 / 206264.806 rad. The printed constant 206264.806 is rounded at
  // 1.2e-9 relative, so compare to it at 1e-8 relative and to the exact pi-form at 1e-15.
  const double four_arcsec = u::parse_as("4 arcsec", u::kAngle);
  EXPECT_NEAR(four_arcsec, 4.0 / 206264.806, 4.0 / 206264.806 * 1e-8);
  EXPECT_NEAR(four_arcsec, 4.0 / kArcsecPerRadRef, 4.0 / kArcsecPerRadRef * 1e-15);
  EXPECT_NEAR(u::parse_as("1 arcmin", u::kAngle), kPi / (180.0 * 60.0), 1e-18);
  EXPECT_NEAR(u::parse_as("2 mrad", u::kAngle), 2e-3, 1e-18);
  EXPECT_NEAR(u::parse_as("1 rad", u::kAngle), 1.0, 0.0);
  EXPECT_NEAR(u::parse_as("-30 deg", u::kAngle), -kPi / 6.0, 1e-15);
}

TEST(Units, AccelerationAndCompoundUnits) {
  const u::Quantity g = u::parse_quantity("9.81 m/s^2");
  EXPECT_EQ(g.dim, u::kAcceleration);
  EXPECT_DOUBLE_EQ(g.value, 9.81);
  EXPECT_DOUBLE_EQ(u::parse_as("9.81 m/s^2", u::kAcceleration), 9.81);

  // kg*m^2: moment of inertia, dimension m^2 kg.
  const u::Quantity j = u::parse_quantity("2.5 kg*m^2");
  const u::Dimension inertia{{2, 1, 0, 0, 0, 0}};
  EXPECT_EQ(j.dim, inertia);
  EXPECT_DOUBLE_EQ(j.value, 2.5);
  EXPECT_DOUBLE_EQ(u::unit_factor("kg*m^2"), 1.0);
  // g*mm^2 = 1e-3 * 1e-6 kg m^2.
  const u::Quantity j2 = u::parse_quantity("3 g*mm^2");
  EXPECT_EQ(j2.dim, inertia);
  EXPECT_NEAR(j2.value, 3e-9, 3e-9 * 1e-14);

  // N*m is a torque, as is the single word Nm.
  EXPECT_EQ(u::parse_quantity("1 N*m").dim, u::kTorque);
  EXPECT_EQ(u::parse_quantity("1 Nm").dim, u::kTorque);
  // Negative exponent.
  EXPECT_EQ(u::parse_quantity("1 s^-1").dim, u::kFrequency);
  EXPECT_EQ(u::parse_quantity("1 kg*m/s^2").dim, u::kForce);
  EXPECT_EQ(u::parse_quantity("1 Pa").dim, u::kPressure);
}

TEST(Units, RotationRate) {
  const u::Dimension angle_per_time{{0, 0, -1, 0, 1, 0}};
  const double expected = 80.0 * 2.0 * kPi / 60.0;  // 8.37758 rad/s
  const u::Quantity a = u::parse_quantity("80 r/min");
  const u::Quantity b = u::parse_quantity("80 rpm");
  EXPECT_EQ(a.dim, angle_per_time);
  EXPECT_EQ(b.dim, angle_per_time);
  EXPECT_NEAR(a.value, expected, expected * 1e-15);
  EXPECT_NEAR(b.value, expected, expected * 1e-15);
  // Also composable: rev/min and deg/s.
  EXPECT_NEAR(u::parse_quantity("80 rev/min").value, expected, expected * 1e-15);
  EXPECT_EQ(u::parse_quantity("80 rev/min").dim, angle_per_time);
  EXPECT_EQ(u::parse_quantity("1 deg/s").dim, angle_per_time);
  // An angular rate is not a frequency: angle is a dimension of its own.
  EXPECT_NE(a.dim, u::kFrequency);
}

TEST(Units, PixelsAndPercent) {
  const u::Quantity px = u::parse_quantity("1 px");
  EXPECT_EQ(px.dim, u::kPixel);
  EXPECT_EQ(px.value, 1.0);
  EXPECT_EQ(u::parse_as("3 pixel", u::kPixel), 3.0);
  // A pixel is not an angle: no implicit IFOV.
  expect_error([] { u::parse_as("1 px", u::kAngle); },
               {"wrong unit: got a pixel count, expected an angle"});

  EXPECT_NEAR(u::parse_as("5 %", u::kDimensionless), 0.05, 1e-17);
  EXPECT_NEAR(u::parse_as("5%", u::kDimensionless), 0.05, 1e-17);
  EXPECT_NEAR(u::parse_as("2 ppm", u::kDimensionless), 2e-6, 1e-21);
  EXPECT_EQ(u::parse_as("0.4", u::kDimensionless), 0.4);
}

TEST(Units, ErrorMissingUnit) {
  expect_error([] { u::parse_as("82", u::kLength); },
               {"missing unit", "expected a length", "\"1 mm\""});
  expect_error([] { u::parse_as("30", u::kAngle); }, {"missing unit", "expected an angle"});
}

TEST(Units, ErrorWrongUnit) {
  expect_error([] { u::parse_as("30 mm", u::kAngle); },
               {"wrong unit: got a length, expected an angle", "deg"});
  expect_error([] { u::parse_as("30 deg", u::kLength); },
               {"wrong unit: got an angle, expected a length"});
  // Unnamed dimensions are spelled out in SI base units.
  expect_error([] { u::parse_as("1 kg*m^2", u::kTorque); },
               {"wrong unit: got a quantity in m^2*kg, expected a torque"});
}

TEST(Units, ErrorUnknownUnit) {
  expect_error([] { u::parse_as("3 furlong", u::kLength); },
               {"unknown unit \"furlong\"", "expected a length"});
  expect_error([] { u::parse_quantity("3 m*furlong"); }, {"unknown unit \"furlong\""});
  EXPECT_THROW(u::unit_factor("furlong"), Error);
}

TEST(Units, ErrorNoNumber) {
  expect_error([] { u::parse_as("mm", u::kLength); }, {"no number", "\"mm\""});
  expect_error([] { u::parse_as("abc deg", u::kAngle); }, {"no number"});
  expect_error([] { u::parse_as("", u::kLength); }, {"empty value"});
  expect_error([] { u::parse_as("   ", u::kLength); }, {"empty value"});
  expect_error([] { u::parse_quantity("inf mm"); }, {"not finite"});
}

TEST(Units, ErrorNoSpace) {
  expect_error([] { u::parse_as("82mm", u::kLength); },
               {"expected a space between number and unit", "\"82mm\""});
}

TEST(Units, ErrorMalformedExponentAndUnit) {
  expect_error([] { u::parse_as("1 m^x", u::kLength); }, {"malformed exponent", "\"m^x\""});
  expect_error([] { u::parse_quantity("1 m^2.5"); }, {"malformed exponent"});
  expect_error([] { u::parse_quantity("1 m^"); }, {"malformed exponent"});
  expect_error([] { u::parse_quantity("1 m/"); }, {"malformed unit"});
  expect_error([] { u::parse_quantity("1 m**s"); }, {"malformed unit"});
}

TEST(Units, Format) {
  EXPECT_EQ(u::format(1.5e-5, "mm"), "0.015 mm");
  EXPECT_EQ(u::format(0.082, "mm"), "82 mm");
  EXPECT_EQ(u::format(kPi / 6.0, "deg"), "30 deg");
  EXPECT_EQ(u::format(4.0 / kArcsecPerRadRef, "arcsec"), "4 arcsec");
  EXPECT_EQ(u::format(1.0 / 3.0, "", 3), "0.333");
  // Round trip through the parser to 1e-12 relative (6 significant digits printed exactly here).
  EXPECT_NEAR(u::parse_as(u::format(2.5e-6, "mm"), u::kLength), 2.5e-6, 2.5e-6 * 1e-12);
  EXPECT_THROW(u::format(1.0, "furlong"), Error);
}

TEST(Units, DimensionNamesAndExamples) {
  EXPECT_EQ(u::dimension_name(u::kLength), "a length");
  EXPECT_EQ(u::dimension_name(u::kAngle), "an angle");
  EXPECT_EQ(u::dimension_name(u::kAcceleration), "an acceleration");
  EXPECT_EQ(u::dimension_name(u::Dimension{{2, 1, 0, 0, 0, 0}}), "a quantity in m^2*kg");
  EXPECT_EQ(u::example_unit(u::kAngle), "deg");
  EXPECT_EQ(u::example_unit(u::kLength), "mm");
  // Every example unit parses to its own dimension.
  for (const auto& d : {u::kLength, u::kMass, u::kTime, u::kCurrent, u::kAngle, u::kPixel,
                        u::kFrequency, u::kForce, u::kTorque, u::kPressure, u::kAcceleration}) {
    EXPECT_EQ(u::parse_quantity("1 " + u::example_unit(d)).dim, d) << u::example_unit(d);
  }
  // A density reads as one, and a composite dimension as its SI units with powers below a
  // slash, which parse back.
  EXPECT_EQ(u::dimension_name(u::kDensity), "a density");
  EXPECT_EQ(u::example_unit(u::kDensity), "kg/m^3");
  const u::Dimension odd{{-2, 1, -1, 0, 0, 0}};
  EXPECT_EQ(u::dimension_name(odd), "a quantity in kg/m^2/s");
  EXPECT_EQ(u::parse_quantity("1 " + u::example_unit(odd)).dim, odd);
  EXPECT_EQ(u::dimension_name(u::Dimension{{0, 0, -1, 1, 0, 0}}), "a quantity in A/s");
  EXPECT_EQ(u::parse_quantity("1 " + u::example_unit(u::Dimension{{0, 0, -2, 0, 0, 0}})).dim,
            (u::Dimension{{0, 0, -2, 0, 0, 0}}));
}

// A value of megabytes is quoted by its start and its length: the message stays a line.
TEST(Units, MessagesStayShortWhateverTheInput) {
  const std::string huge = "56 " + std::string(2000000, 'x');
  try {
    (void)u::parse_as(huge, u::kLength);
    FAIL() << "a unit of 2 MB parsed";
  } catch (const poise::Error& e) {
    const std::string what = e.what();
    EXPECT_LT(what.size(), 400u) << what.substr(0, 400);
    EXPECT_NE(what.find("(2000000 bytes)"), std::string::npos) << what.substr(0, 400);
  }
}

}  // namespace
