#include "balancing/iso_figures.h"

#include <algorithm>
#include <cmath>

namespace poise::balancing {

IsoFigures iso_figures(const BalancingCampaign& c, const CampaignAnalysis& a) {
  IsoFigures out;
  // URR: each check run's indication of each test mass it carries.
  for (const auto& r : a.runs) {
    if (!r.check || !r.applied) continue;
    for (std::size_t p = 0; p < c.planes.size(); ++p) {
      const estimators::Phasor t = (*r.applied)[p];
      if (std::abs(t) == 0.0) continue;
      const auto& d = r.unbalance.planes[p];
      const double miss = std::abs(d.value - t), size = std::abs(t);
      IsoUrrFigure f{r.name, c.planes[p], 1.0 - miss / size, std::nullopt, std::nullopt};
      if (const auto rho = d.radius()) {
        f.lower = 1.0 - (miss + *rho) / size;
        f.upper = 1.0 - std::max(0.0, miss - *rho) / size;
      }
      out.urr.push_back(f);
    }
  }
  // U_mar: the indicated amounts of the runs of the U_mar test, per plane.
  for (std::size_t p = 0; p < c.planes.size(); ++p) {
    std::vector<double> amount, rho;
    for (const auto& r : a.runs) {
      if (!r.check || r.declared >= c.umar_run.size() || !c.umar_run[r.declared]) continue;
      const auto& d = r.unbalance.planes[p];
      // In the campaign's declared sense both; their sum is the indicated unbalance.
      amount.push_back(std::abs(a.initial_unbalance.planes[p].value + d.value));
      const auto rd = d.radius(), r0 = a.initial_unbalance.planes[p].radius();
      if (rd && r0) rho.push_back(*rd + *r0);
    }
    if (amount.size() < 2) continue;
    const double factor = c.plane_radius[p] > 0.0 ? c.plane_radius[p] * 1e3 : 1.0;  // g -> g mm
    const auto [lo, hi] = std::minmax_element(amount.begin(), amount.end());
    IsoUmarFigure f{c.planes[p],  amount.size(), (*hi - *lo) / 2.0 * factor,
                    std::nullopt, std::nullopt,  c.plane_radius[p] > 0.0 ? "g mm" : "g"};
    if (rho.size() == amount.size()) {
      const double widest = *std::max_element(rho.begin(), rho.end());
      f.lower = std::max(0.0, (*hi - *lo) / 2.0 - widest) * factor;
      f.upper = ((*hi - *lo) / 2.0 + widest) * factor;
    }
    out.umar.push_back(f);
  }
  return out;
}

}  // namespace poise::balancing
