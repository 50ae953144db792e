// The shaft_sag study kind: the LOS tilt of a gimbal's optics from the gravity sag of its
// shaft (shaft_sag.h), over the shaft's and the load's tolerances. A closed-form kind: the
// engine does everything but the formula (engine/kind_interface/closed_form_kind.h).
#include <memory>

#include "core/error.h"
#include "engine/kind_interface/closed_form_kind.h"
#include "kinds/shaft_sag/shaft_sag.h"

namespace poise::kinds::shaft_sag {
using namespace poise::engine;
namespace {

using units::kDimensionless;
using units::kLength;

class ShaftSagKind final : public ClosedFormKind {
 public:
  ShaftSagKind()
      : ClosedFormKind({"shaft_sag",
                        "LOS tilt of a gimbal's optics from the gravity sag of its shaft (simply supported, point "
                        "load between the bearings, Euler-Bernoulli), over the shaft's and the load's tolerances "
                        "(model: e.g. models/shaft_sag_example.toml)",
                        {{"span", kLength, "mm", "bearing span L"},
                         {"load_position", kLength, "mm", "distance a of the optics' centre of mass from bearing A"},
                         {"diameter", kLength, "mm", "outer diameter d of the shaft"},
                         {"bore", kLength, "mm", "bore diameter d_i (0 for a solid shaft)"},
                         {"youngs_modulus", units::kPressure, "GPa", "Young's modulus E of the shaft"},
                         {"load_mass", units::kMass, "g", "mass m of the optics carried"},
                         {"gravity", units::kAcceleration, "m/s^2", "gravity g"},
                         {"los_per_tilt", kDimensionless, "1", "LOS turn per radian of tilt (1 lens, 2 mirror)"}},
                        {{"tilt_urad", "urad", "tilt of the shaft at the optics"},
                         {"los_error_arcsec", "arcsec", "LOS error from the tilt: |los_per_tilt x tilt|"},
                         {"deflection_um", "um", "sag of the shaft at the optics"}},
                        {}}) {}

  std::vector<double> compute(std::span<const double> p) const override {
    const double span = p[0], a = p[1], d = p[2], bore = p[3], e = p[4], m = p[5], g = p[6], k = p[7];
    if (!(a >= 0.0 && a <= span)) throw Error("load off the shaft: load_position outside 0..span");
    if (!(bore >= 0.0 && bore < d)) throw Error("no shaft: bore diameter not below the outer diameter");
    if (!(e > 0.0 && span > 0.0)) throw Error("non-physical draw: Young's modulus and span must be positive");
    const kinds::shaft_sag::ShaftSag s = kinds::shaft_sag::shaft_sag(span, a, d, bore, e, m * g);
    return {s.slope, std::abs(k * s.slope), s.deflection};
  }
};

}  // namespace

std::unique_ptr<StudyKind> make_shaft_sag_kind() { return std::make_unique<ShaftSagKind>(); }

}  // namespace poise::kinds::shaft_sag
