#pragma once
/// A tolerance as written in a model file:
///   [yaw.radial_runout]
///   tolerance = "0.0025 mm"      # +-t (or the magnitude limit of a run-out)
///   distribution = "normal"      # normal | uniform | arcsine | truncated_normal | fixed
///   tolerance_is = "3sigma"      # bounds | 1sigma | 2sigma | 3sigma
///   source = "Wang 2011, Sec. 2.1.1 (3) 1)"
/// or a drawing's asymmetric limits (the distribution centred between them, t their half-width):
///   deviation = ["0 mm", "+0.06 mm"]
///   distribution = "normal"
///   tolerance_is = "3sigma"
/// or, for a parameter with a range rather than a deviation:
///   min = 0.4
///   max = 0.96
///   distribution = "uniform"     # read as bounds
#include <string>

#include "core/units.h"
#include "engine/study_files/toml_reader.h"
#include "sampling/distribution.h"

namespace poise::engine {

struct ToleranceSpec {
  sampling::Distribution dist{sampling::DistributionKind::kFixed, 0.0, 0.0, sampling::ToleranceConvention::kBounds};
  double tolerance = 0.0;  ///< t as written (SI), for the analytic budget
  std::string source;
  std::string display_unit;  ///< unit for reports ("mm", "arcsec", "")
  double display_factor = 1.0;
};

/// A tolerance with its scope in a procedure study:
///   scope = "unit"  drawn once per Monte Carlo sample (the hardware as built);
///   scope = "test"  drawn again for every test run of that sample.
struct ScopedTolerance {
  ToleranceSpec spec;
  bool per_test = false;  ///< scope = "test"
};

/// Reads a tolerance table at `key` with values of dimension `dim` (dimensionless specs
/// may use min/max as plain numbers). Errors are recorded in the reader's context.
ToleranceSpec read_tolerance(TomlReader& parent, const std::string& key, const units::Dimension& dim,
                             const std::string& display_unit);

/// read_tolerance plus its `scope` ("unit" or "test").
ScopedTolerance read_scoped_tolerance(TomlReader& parent, const std::string& key, const units::Dimension& dim,
                                      const std::string& display_unit);

}  // namespace poise::engine
