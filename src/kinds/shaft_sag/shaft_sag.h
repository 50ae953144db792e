#pragma once
/// Gravity sag of a gimbal shaft carrying its optics, and the LOS tilt it causes.
///
/// The shaft is a uniform Euler-Bernoulli beam simply supported by its two bearings (span L;
/// bearings as pins: a conservative reading of a duplex pair), loaded by the optics' weight
/// P = m g at a distance a from bearing A (b = L - a). With I = pi (d^4 - d_i^4) / 64
/// (d outer, d_i bore diameter), for 0 <= x <= a (Timoshenko & Gere, Mechanics of Materials,
/// App. G, case 5):
///   y(x)  = P b x (L^2 - b^2 - x^2) / (6 E I L)
///   y'(x) = P b (L^2 - b^2 - 3 x^2) / (6 E I L)
/// so at the load, using L^2 - b^2 = a^2 + 2 a b:
///   deflection  delta = y(a)  = P a^2 b^2 / (3 E I L)
///   slope       theta = y'(a) = P a b (b - a) / (3 E I L)   (zero for a load at mid-span)
/// The optics tilt with the shaft at the load point; the LOS turns by k theta, with k the
/// optics' lever (1 for a lens or camera riding on the shaft, 2 for a mirror: the reflected
/// ray turns twice). The shaft's own weight is left out (it is a model key away if wanted).
/// Checked in tests/cli/shaft_sag_test.cc against a numerical double integration of M(x) / (E I)
/// with the supports' conditions, and by symmetry and mid-span limits.
#include <cmath>

namespace poise::kinds::shaft_sag {

struct ShaftSag {
  double deflection = 0.0;  ///< m, at the load, downwards
  double slope = 0.0;       ///< rad, at the load
};

/// The sag at the load of a simply supported shaft (SI). Requires 0 <= a <= L, E I > 0.
inline ShaftSag shaft_sag(double span, double load_position, double outer_diameter, double bore_diameter,
                          double youngs_modulus, double load) {
  const double pi = 3.14159265358979323846;
  const double a = load_position, b = span - load_position;
  const double ei = youngs_modulus * pi * (std::pow(outer_diameter, 4) - std::pow(bore_diameter, 4)) / 64.0;
  return {load * a * a * b * b / (3.0 * ei * span), load * a * b * (b - a) / (3.0 * ei * span)};
}

}  // namespace poise::kinds::shaft_sag
