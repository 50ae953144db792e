#pragma once
// The rotor the influence-coefficient tests share: two planes, three sensors; its own readings
// a (kA) and the coefficients h (kH, per sensor and plane), in a reading unit per gram.
#include <complex>
#include <vector>

#include "estimators/influence_coefficients.h"

namespace poise::estimators::test_rotor {

inline const std::vector<Phasor> kA = {std::polar(1.2, 0.4), std::polar(0.7, 2.0), std::polar(1.9, -1.0)};
inline const std::vector<std::vector<Phasor>> kH = {{std::polar(0.08, 1.0), std::polar(0.02, -0.5)},
                                                    {std::polar(0.05, 2.5), std::polar(0.06, 0.3)},
                                                    {std::polar(0.01, -2.0), std::polar(0.09, 1.7)}};

}  // namespace poise::estimators::test_rotor
