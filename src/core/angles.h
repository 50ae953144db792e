#pragma once
/// Pi and angle wrapping, one definition for every layer.
#include <cmath>
#include <numbers>

namespace poise::angles {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// x wrapped into [0, 2 pi) (fmod of a tiny negative number plus 2 pi can round to 2 pi
/// itself: that gives 0).
inline double wrap_two_pi(double x) {
  double w = std::fmod(x, kTwoPi);
  if (w < 0.0) w += kTwoPi;
  return w >= kTwoPi ? 0.0 : w;
}

/// x wrapped into [-pi, pi] (the nearest representative of x about 0).
inline double wrap_pi(double x) { return std::remainder(x, kTwoPi); }

}  // namespace poise::angles
