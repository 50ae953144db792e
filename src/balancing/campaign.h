#pragma once
/// A balancing campaign file and its readings (`poise balance CAMPAIGN.toml`, Python's
/// poise.balance):
///
///     [campaign]
///     name = "compressor, field balance 2004"
///     readings = "readings.csv"      # relative to this file; one row per reading of a run
///     amplitude_unit = "mil"         # the amplitudes' unit where the header gives none
///     phase = "lag"                  # "lag" (default) or "lead": how the instrument gives phase
///
///     [[sensor]]                     # one per probe, in any order
///     name = "fwd_x"
///     amplitude = "FwdX amp"         # the readings file's headers of its amplitude and phase
///     phase = "FwdX phase"
///     angle = "225 deg"              # optional: added to its phases (a probe's mounting angle)
///
///     [[plane]]
///     name = "aft"
///     radius = "120 mm"              # optional: masses at another radius are scaled to it
///
///     [[run]]                        # in the order of the readings file's `run` column (1, 2, ...)
///     name = "as found"
///     masses = []                    # no mass added; omit `masses` for a rotor of unknown masses
///     [[run]]
///     name = "aft trial"
///     masses = [{plane = "aft", mass = "11.1 g", angle = "35 deg"}]
///     [[run]]
///     name = "check"
///     check = true                   # masses known but left out of the calibration: the
///     masses = [...]                 #   answer for this run is compared with them
///
/// Weight angles and phases are counted in one sense from the key phasor (the instrument's); the
/// answers are given in that sense. The readings file is a lab's table (estimators/lab_table.h):
/// a `run` column (the run's number) and each sensor's two columns; a run may have several rows
/// (repeated readings), each one observation.
#include <string>
#include <vector>

#include "estimators/influence_coefficients.h"

namespace poise::balancing {

struct BalancingCampaign {
  std::string file, name, amplitude_unit;
  std::vector<std::string> sensors, planes;
  std::vector<double> plane_radius;            ///< m, 0 where not given
  std::vector<estimators::BalancingRun> runs;  ///< one per reading row, named after its [[run]]
  std::size_t declared_runs = 0;
};

/// Reads the campaign and its readings. Throws ValidationError / InputError with file, line,
/// key and what was expected.
BalancingCampaign read_balancing_campaign(const std::string& path);

}  // namespace poise::balancing
