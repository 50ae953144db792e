#pragma once
/// A balancing campaign file and its readings (`poise balance CAMPAIGN.toml`, Python's
/// poise.balance):
///
///     [campaign]
///     name = "compressor, field balance 2004"
///     readings = "readings.csv"      # relative to this file
///     amplitude_unit = "mil"         # the amplitudes' unit where the header gives none
///                                    #   (a displacement, "mm/s", "m/s^2" or "gn": any one kind)
///     phase = "lag"                  # "lag" (default) or "lead": how the instrument gives phase
///     weight_angles = "against_rotation"  # (default) or "with_rotation": how masses' angles count
///     layout = "wide"                # "wide" (default): a row per reading of a run, two columns
///                                    #   per sensor; "long": a row per sensor's reading
///     balancing_speed = "8610 rpm"   # with several speeds: the one answered first (default: highest)
///     reading_noise = "0.02 mil"     # optional: the instrument's reading noise (RMS size of a
///                                    #   reading's error), used only where the runs leave no
///                                    #   degrees of freedom: regions from it alone
///
///     [columns]                      # optional: the readings file's headers, where not the defaults
///     run = "Run"                    # the run: its number (1, 2, ... the [[run]] tables in order)
///                                    #   or its name (default header "run")
///     speed = "RPM"                  # optional: the speed, unit in the header or rpm ("speed",
///                                    #   "speed_rpm", "rpm")
///     sensor = "Probe"               # long layout: the sensor's name ("sensor"), and its reading
///     amplitude = "Amp"              #   as "amplitude" and "phase", or "real" and "imaginary"
///     phase = "Phase"
///
///     [[sensor]]                     # one per probe, in any order
///     name = "fwd_x"
///     amplitude = "FwdX amp"         # wide layout: the headers of its amplitude and phase,
///     phase = "FwdX phase"           #   or `real = ".."` and `imaginary = ".."`, or
///                                    #   `reading = ".."`: cells as "2.07 @ 335" (degrees)
///     angle = "225 deg"              # optional: added to its phases (a probe's mounting angle)
///
///     [[plane]]
///     name = "aft"
///     radius = "120 mm"              # optional: masses at another radius are scaled to it
///     holes = 12                     # optional: correction only at 12 equally spaced holes,
///     first_hole = "0 deg"           #   the first at this angle: each correction is split onto
///                                    #   the two holes beside it
///
///     [[run]]                        # in the order of the run numbers
///     name = "as found"
///     masses = []                    # no mass added; omit `masses` for a rotor of unknown masses
///     [[run]]
///     name = "aft trial"
///     masses = [{plane = "aft", mass = "11.1 g", angle = "35 deg"}]
///     [[run]]
///     name = "check"
///     check = true                   # masses known but left out of the calibration: the
///     masses = [...]                 #   answer for this run is compared with them
///     umar = true                    # optional, with check: a run of ISO 21940-21's U_mar test
///                                    #   (test masses in both planes moved together)
///
///     [design]                       # optional: the machine's design study (a balancing_machine
///     study = "machine.toml"         #   study), run here; the real figures are placed in its
///     samples = 64                   #   simulated distributions
///     [[design.compare]]
///     figure = "urr"                 # "urr" (the check runs' mean in that plane), "umar", or
///                                    #   "influence": |h| of `sensor` and plane (readings in a
///                                    #   force per unbalance: the plane's radius is needed)
///     plane = "left"
///     output = "urr_iso_plane1_pct"  # the study's output it is compared with
///     sensor = "left"                # influence only: the campaign's sensor
///     [design.calibrate]             # optional: one model key fitted to the influence figures
///     key = "torsional_plate.thickness"   # (a calibration: the study's mean |h| made equal to the
///     range = ["3 mm", "5 mm"]       #   real ones in weighted least squares, within the range)
///
/// Conventions. Inside Poise phases are lags and masses' angles count against rotation, both from
/// the reference mark (a heavy spot further against rotation passes a probe later: a larger lag),
/// so that a reading is linear in m e^{i angle}; a lead or angles with rotation are turned round
/// on reading, and the answers are given back in the campaign's declared sense. A reference mark
/// that sits elsewhere turns every reading by one angle, which the coefficients absorb: the
/// masses found do not depend on it. Each sensor's readings (a row) at one speed are one
/// observation; readings at speeds within 2% of each other are one speed.
#include <optional>
#include <string>
#include <vector>

#include "estimators/influence_coefficients.h"

namespace poise::balancing {

/// A real figure of the campaign beside an output of the machine's design study.
struct DesignCompare {
  std::string figure, plane, output;
  std::string sensor;  ///< figure "influence" only
};
/// A model key of the design study fitted to the campaign's influence figures.
struct DesignCalibrate {
  std::string key;
  std::string unit;              ///< the range's unit, as written ("" for a plain number)
  double low = 0.0, high = 0.0;  ///< in that unit
  int line = 0;                  ///< of [design.calibrate] in the campaign file
};
struct DesignLink {
  std::string study;  ///< path (relative ones are read from the campaign's folder)
  std::size_t samples = 64;
  std::vector<DesignCompare> compare;
  std::optional<DesignCalibrate> calibrate;
};

struct BalancingCampaign {
  std::string file, name, amplitude_unit;
  bool weights_with_rotation = false;  ///< answers' angles count with rotation (declared)
  bool phase_lead = false;             ///< the instrument gives phase lead (declared)
  std::vector<double> sensor_angle;    ///< rad: each probe's mounting angle
  std::vector<double> speeds_rpm;      ///< the distinct speeds, ascending (empty: none given)
  std::optional<double> balancing_speed_rpm;
  std::optional<double> reading_noise;  ///< in amplitude_unit
  std::vector<std::string> sensors, planes;
  std::vector<double> plane_radius;            ///< m, 0 where not given
  std::vector<int> plane_holes;                ///< equally spaced holes, 0 where any angle will do
  std::vector<double> plane_first_hole;        ///< rad, in the declared sense of masses' angles
  std::vector<estimators::BalancingRun> runs;  ///< one per reading row, named after its [[run]]
  std::size_t declared_runs = 0;
  std::vector<bool> umar_run;  ///< per declared run: a run of the U_mar test
  std::optional<DesignLink> design;
};

/// Reads the campaign and its readings. Throws ValidationError / InputError with file, line,
/// key and what was expected.
BalancingCampaign read_balancing_campaign(const std::string& path);

}  // namespace poise::balancing
