#pragma once
/// A raw record of one turntable position, read from a CSV file, for `poise diagnose-record`
/// (estimators/oscillation_diagnosis.h) and written by `poise simulate-record`.
///
/// File format (plain CSV, comma-separated, no quoting; CRLF line ends and blank lines are
/// accepted):
///
///     time_s,current_A,phi_deg
///     0.000000,0.0123,0.51
///     ...
///
/// - time_s: time, s (uniformly sampled; diagnose_oscillation checks it)
/// - current_A: drive current, A
/// - phi_deg: gimbal angle, deg
/// - any other column is ignored.
#include <string>

#include "estimators/oscillation_diagnosis.h"

namespace poise::estimators {

/// Reads a record (format above); each sample keeps its file line for later messages.
/// Throws poise::Error naming the file and the line for: a file that cannot be read, a
/// missing column, a row with another number of cells than the header; poise::InputError
/// (file, line, column, the cell cut to a screen line) for a cell that is not a finite number.
OscillationRecord read_oscillation_record(const std::string& path);

}  // namespace poise::estimators
