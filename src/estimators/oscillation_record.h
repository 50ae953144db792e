#pragma once
/// A raw record of one axis (time, drive current or torque, angle), read from a lab's file as it
/// comes, for `poise diagnose-record` (estimators/oscillation_diagnosis.h) and written by
/// `poise simulate-record`.
///
/// Columns by role (estimators/lab_table.h: delimiters, comments, units in headers, --column
/// and --unit):
/// - time: s by default, header `time_s`; jittered stamps and gaps are used as they are, a
///   stamp that repeats or goes back is an error (diagnose_oscillation). A file without time
///   is a quasi-static map: its rows are taken in their order (record_motion.h);
/// - current: drive current, A by default, header `current_A`; or torque: N*m, header
///   `torque_Nm` (then K_T is not used);
/// - angle: the axis angle, deg by default, header `phi_deg`; an angle that wraps (a jump of
///   more than half a turn between two rows, as a single-turn encoder's does) is unwrapped;
/// - velocity (optional): rad/s by default, header `velocity_rad_s`; used for the direction of
///   motion where the file has it.
/// Any other column is ignored. The default headers are what `poise simulate-record` writes:
///
///     time_s,current_A,phi_deg
///     0.000000,0.0123,0.51
#include <string>
#include <vector>

#include "estimators/lab_table.h"
#include "estimators/oscillation_diagnosis.h"

namespace poise::estimators {

/// The column roles of a record (time, current, torque, angle, velocity) with their defaults.
const std::vector<ColumnRole>& record_column_roles();

/// Reads a record (format above); each sample keeps its file line for later messages, and what
/// the reading did (the delimiter, each column's header and unit, angle unwraps) is in `notes`.
/// Throws poise::InputError (file, line, column, cell, what was expected) for a cell that is not
/// a finite number, a missing column, a column of unknown unit; poise::Error for a file that
/// cannot be read.
OscillationRecord read_oscillation_record(const std::string& path, const ColumnMapping& mapping = {});

}  // namespace poise::estimators
