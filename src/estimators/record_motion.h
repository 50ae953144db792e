#pragma once
/// The motion a raw record holds, recognised before anything is fitted, so that only what
/// this motion can show is estimated (estimators/record_map_diagnosis.h,
/// estimators/oscillation_diagnosis.h):
///   swing  the axis oscillates about a position, less than half a turn peak to peak, with
///          reversals (the static-unbalance test's motion): inertia, damping, friction, the
///          spring, and cogging orders that complete a cycle over the swing;
///   steps  a quasi-static map: the axis stepped from position to position and held (most rows
///          at rest), or a file without time, whose rows are taken in their order as such a
///          map: the torque against angle, per direction; no velocity or acceleration, so no
///          inertia or damping;
///   laps   the axis turning at a roughly steady speed, in one direction or both: the torque
///          against angle over the turns covered; no acceleration to show inertia, and one
///          speed per direction cannot separate damping from friction.
/// Rate and direction come from the record's signals (oscillation_detail.h): the local
/// quadratic's rate on the actual time stamps, the direction its sign (a zero rate taking the
/// last nonzero sign). A row is moving where the angle's step to it is at least 10 % of the
/// 90th percentile of the steps; a reversal is a change of direction with at least one
/// derivative window of rows on each side.
#include <cstddef>
#include <string>

namespace poise::estimators {

struct RecordMotion {
  std::string kind;                        ///< "swing", "steps", "laps"
  bool timed = true;                       ///< false: no time column; the rows are a map in file order
  bool forward = false, backward = false;  ///< directions with at least 10 % of the moving rows
  double span = 0.0;                       ///< rad, max - min of the (unwrapped) angle
  double turns = 0.0;                      ///< span / 2 pi
  std::size_t reversals = 0;
  double moving_share = 0.0;     ///< of the rows
  double speed = 0.0;            ///< rad/s (rad per row without time): median |rate| of the moving rows
  double speed_variation = 0.0;  ///< interquartile range of |rate| over the moving rows / its median
  std::string description;  ///< one sentence, e.g. "laps at a steady speed, forward only: 0.996 turn at 0.0996 turn/s"
};

}  // namespace poise::estimators

#include "estimators/oscillation_diagnosis.h"

namespace poise::estimators {

/// The motion of a record (checks and errors as diagnose_oscillation's).
RecordMotion record_motion(const OscillationRecord& rec, const OscillationOptions& opt);

}  // namespace poise::estimators
