#include "kinds/balancing_machine/balancing_iso_tests.h"

#include <algorithm>
#include <cmath>

#include "core/units.h"

namespace poise::kinds::balancing_machine {

IsoUrr iso_urr(IsoBench& bench, const std::vector<models::PlaneMass>& rotor, double mass, double radius) {
  const Eigen::Vector2cd bare = bench.indicate(rotor);
  std::vector<models::PlaneMass> loaded = rotor;
  loaded.push_back(bench.place(mass, radius, 0.0, bench.plane_1_height));
  loaded.push_back(bench.place(mass, radius, 0.5 * units::kPi, bench.plane_2_height));
  const Eigen::Vector2cd with = bench.indicate(loaded);
  // The known test unbalances: nominal mass at the nominal radius and angle.
  const std::complex<double> known[2] = {mass * radius, mass * radius * std::polar(1.0, 0.5 * units::kPi)};
  IsoUrr out;
  for (int p = 0; p < 2; ++p) out.plane[p] = 1.0 - std::abs(with(p) - bare(p) - known[p]) / std::abs(known[p]);
  return out;
}

TwoPlaneUmar two_plane_umar(IsoBench& bench, const std::vector<models::PlaneMass>& rotor, double mass, double radius,
                            int positions, double plane_2_offset, double claim) {
  TwoPlaneUmar out;
  for (int k = 0; k < positions; ++k) {
    const double phi = 2.0 * units::kPi * k / positions;
    std::vector<models::PlaneMass> loaded = rotor;
    loaded.push_back(bench.place(mass, radius, phi, bench.plane_1_height));
    loaded.push_back(bench.place(mass, radius, phi + plane_2_offset, bench.plane_2_height));
    const Eigen::Vector2cd ind = bench.indicate(loaded);
    for (int p = 0; p < 2; ++p) out.readings[p].push_back(std::abs(ind(p)) / radius);
  }
  out.pass = true;
  for (int p = 0; p < 2; ++p) {
    const auto& r = out.readings[p];
    double mean = 0.0;
    for (double v : r) mean += v / static_cast<double>(r.size());
    out.mean[p] = mean;
    for (double v : r) out.max_deviation[p] = std::max(out.max_deviation[p], std::abs(v - mean));
    const auto [mn, mx] = std::minmax_element(r.begin(), r.end());
    out.umar[p] = (*mx - *mn) * radius / 2.0;
    out.pass = out.pass && out.max_deviation[p] * radius <= claim;
  }
  return out;
}

}  // namespace poise::kinds::balancing_machine
