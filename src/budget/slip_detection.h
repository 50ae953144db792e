#pragma once
/// The likely slip behind a declared figure that does not follow from its inputs. Each
/// candidate recomputes the figure as the author may have done it, and is named when it
/// reproduces the declared value within the 1% of the verdict (at both ends of a range):
///   line:  the tolerance read with another convention ("bounds read as sigma: the declared
///          value is sqrt(3) x the recomputed one", "a 3-sigma tolerance read as 1 sigma") or
///          another distribution; a level mix-up (x2, x3 between 1, 2 and 3 sigma); the gain
///          left out, inverted, or evaluated with angles in degrees as if radians; the lever of
///          another line; a unit factor (degrees/radians 57.3, arcmin/arcsec 60, 3600, 1000,
///          206265); else the single change that would give it ("a lever 0.8 x the stated
///          one (44.8 mm instead of 56 mm), or a tolerance of 0.005 mm instead of 0.004 mm").
///   group or combined figure: it follows from the members' declared values (the slip is
///          upstream, in the members named); another combination rule; a member left out;
///          the propagation factors left out; a level mix-up; a unit factor.
/// An empty string: no candidate explains it.
#include <optional>
#include <string>
#include <vector>

#include "budget/budget_check.h"
#include "budget/budget_evaluation.h"

namespace poise::budget {

/// Slip of line `item` (declared d, recomputed r).
std::string line_slip(const BudgetEvaluator& ev, std::size_t item, const Declared& d, const Range& r);

/// Slip of a group (item) or, with item = nullopt, of the combined figure. `results` holds the
/// verdicts of every item computed so far (by item index), to name the upstream slips.
std::string node_slip(const BudgetEvaluator& ev, std::optional<std::size_t> item, const Declared& d, const Range& r,
                      const std::vector<const ItemResult*>& results);

/// "sqrt(3)", "2", "1/sqrt(2)", or the number with 3 significant digits.
std::string ratio_text(double r);

}  // namespace poise::budget
