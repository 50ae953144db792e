#pragma once
/// The one units module of Poise. Values in study and model files are strings
/// "<number> <unit>", e.g. "0.004 mm", "82 mm", "30 deg", "4 arcsec", "9.81 m/s^2".
/// Inside Poise everything is SI (angles in radians); this module converts.
///
/// Units compose with '*', '/' and '^n' ("kg*m^2", "N*m/rad", "m/s^2", "ppm/K"). Angles and
/// pixels are dimensions of their own, so "30" or "30 m" is refused where an
/// angle is expected. Pixels convert to angles only through an explicit IFOV.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace poise::units {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kArcsecPerRad = 180.0 * 3600.0 / kPi;  // 206264.806...
inline constexpr double kRadPerArcsec = 1.0 / kArcsecPerRad;
inline constexpr double kRadPerDeg = kPi / 180.0;

/// Exponents of length, mass, time, current, plane angle, pixel, temperature.
struct Dimension {
  std::array<std::int8_t, 7> e{};
  friend bool operator==(const Dimension&, const Dimension&) = default;
};

inline constexpr Dimension kDimensionless{};
inline constexpr Dimension kLength{{1, 0, 0, 0, 0, 0}};
inline constexpr Dimension kMass{{0, 1, 0, 0, 0, 0}};
inline constexpr Dimension kTime{{0, 0, 1, 0, 0, 0}};
inline constexpr Dimension kCurrent{{0, 0, 0, 1, 0, 0}};
inline constexpr Dimension kAngle{{0, 0, 0, 0, 1, 0}};
inline constexpr Dimension kPixel{{0, 0, 0, 0, 0, 1}};
/// A temperature difference (K): a change or a spread, never an absolute temperature.
inline constexpr Dimension kTemperature{{0, 0, 0, 0, 0, 0, 1}};
inline constexpr Dimension kFrequency{{0, 0, -1, 0, 0, 0}};
inline constexpr Dimension kForce{{1, 1, -2, 0, 0, 0}};
inline constexpr Dimension kTorque{{2, 1, -2, 0, 0, 0}};
inline constexpr Dimension kPressure{{-1, 1, -2, 0, 0, 0}};
inline constexpr Dimension kAcceleration{{1, 0, -2, 0, 0, 0}};
inline constexpr Dimension kDensity{{-3, 1, 0, 0, 0, 0}};

/// A value in SI units with its dimension.
struct Quantity {
  double value = 0.0;
  Dimension dim{};
};

/// Human name of a dimension, e.g. "length", "angle", "m^2*kg*s^-2".
std::string dimension_name(const Dimension& d);

/// Example unit for a dimension, used in error messages ("mm", "deg", ...).
std::string example_unit(const Dimension& d);

/// Parses "<number> <unit>". Throws poise::Error with a message saying what is wrong
/// (no number, unknown unit, ...). A bare number parses as dimensionless.
Quantity parse_quantity(std::string_view text);

/// Parses and checks the dimension; returns the SI value. Throws poise::Error whose
/// message names the expected dimension and an example ("expected an angle, e.g. \"1 deg\"").
double parse_as(std::string_view text, const Dimension& expected);

/// Formats an SI value in a given unit, e.g. format(1.5e-5, "mm") -> "0.015 mm".
std::string format(double value_si, std::string_view unit, int significant = 6);

/// SI value of one unit of `unit` (e.g. "mm" -> 1e-3). Throws on unknown unit.
double unit_factor(std::string_view unit);

}  // namespace poise::units
