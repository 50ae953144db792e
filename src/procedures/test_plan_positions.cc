// The turntable positions of a static-unbalance test plan and their order
// (static_unbalance_procedure.h: Placement, set_positions).
#include "procedures/static_unbalance_procedure.h"

#include <cstddef>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/units.h"

namespace poise::procedures {

Placement parse_placement(const std::string& name) {
  if (name == "sequential") return Placement::kSequential;
  if (name == "interleaved") return Placement::kInterleaved;
  if (name == "back_and_forth") return Placement::kBackAndForth;
  throw Error("unknown placement '" + name + "': sequential, interleaved or back_and_forth");
}

void set_positions(TestPlan& plan, std::size_t n, Placement placement) {
  std::vector<std::size_t> order;
  order.reserve(n);
  std::vector<int> sweep;
  switch (placement) {
    case Placement::kSequential:
      for (std::size_t k = 0; k < n; ++k) order.push_back(k);
      break;
    case Placement::kInterleaved: {
      // Bit-reversed counting over the next power of two, keeping the indices below n.
      unsigned bits = 0;
      while ((std::size_t{1} << bits) < n) ++bits;
      for (std::size_t k = 0; k < (std::size_t{1} << bits); ++k) {
        std::size_t r = 0;
        for (unsigned b = 0; b < bits; ++b) r |= ((k >> b) & 1u) << (bits - 1 - b);
        if (r < n) order.push_back(r);
      }
      break;
    }
    case Placement::kBackAndForth:
      for (std::size_t k = 0; k < n; k += 2) {
        order.push_back(k);
        sweep.push_back(+1);
      }
      for (std::size_t k = (n % 2 == 0 ? n - 1 : n - 2); k < n; k -= 2) {
        order.push_back(k);
        sweep.push_back(-1);
        if (k < 2) break;
      }
      break;
  }
  plan.positions.clear();
  for (std::size_t k : order) {
    plan.positions.push_back(2.0 * units::kPi * static_cast<double>(k) / static_cast<double>(n));
  }
  plan.sweep = std::move(sweep);
}

}  // namespace poise::procedures
