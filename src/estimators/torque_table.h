#pragma once
/// Measured static unbalance torque against turntable angle, read from a CSV file, for
/// `poise fit` (and `poise diagnose`).
///
/// File format (plain CSV, comma-separated, no quoting; a UTF-8 BOM, CRLF line ends,
/// whitespace around cells and blank lines are accepted):
///
///     theta_deg,torque_mNm
///     0.00,11.94
///     10.00,13.26
///     ...
///
/// - theta_deg (required): turntable angle in degrees.
/// - exactly one torque column whose name carries its unit: torque_mNm (mN*m) or torque_Nm (N*m).
/// - time_s (optional): time of the measurement, s.
/// - sweep (optional): turntable direction of travel, +1 or -1.
/// - torque_se_mNm or torque_se_Nm (optional): standard error of each position's torque from
///   the scatter between its period integrals (sd / sqrt(periods)), > 0: an independent noise
///   level for the lack-of-fit test of `poise diagnose`.
/// - any other column is ignored.
/// At least 4 data rows and at least 3 distinct angles (modulo 360 deg) are required: the sine
/// fit has 3 parameters and needs one more point for the residual spread.
#include <cstddef>
#include <string>
#include <vector>

#include "estimators/lab_table.h"

namespace poise::estimators {

/// The rows of a torque table, in file order. SI inside (rad, N*m); the file's own values
/// are kept beside them so output can repeat them exactly as written.
struct TorqueTable {
  std::string file;               ///< path as given
  std::vector<double> theta_rad;  ///< turntable angle, rad
  std::vector<double> torque_Nm;  ///< torque, N*m
  std::vector<double> theta_deg;  ///< turntable angle as written, deg
  std::vector<double> torque;     ///< torque as written, in `unit`
  std::string torque_column;      ///< "torque_mNm" or "torque_Nm"
  std::string unit;               ///< "mN*m" or "N*m"
  double unit_factor = 1.0;       ///< N*m per file unit: 1e-3 for mN*m, 1 for N*m
  std::vector<std::size_t> rows;  ///< 1-based file line of each row (the header is line 1)
  std::vector<double> time_s;     ///< column time_s, s; empty when the file has none
  std::vector<int> sweep;         ///< column sweep, +1 or -1; empty when the file has none
  std::vector<double> torque_se;  ///< column torque_se_*, in `unit`; empty when none

  std::size_t size() const { return theta_rad.size(); }
};

/// Reads a torque table (format above). Throws poise::Error naming the file, the line
/// (1-based, header = line 1), the column and the bad cell for: a file that cannot be read,
/// a missing theta_deg column, no or two torque columns, a repeated column name, a row with
/// a different number of cells than the header, an empty, non-numeric or non-finite cell, a
/// torque or standard error beyond 1e9 N*m in magnitude (its squares would overflow the fits),
/// a sweep other than +1/-1, fewer than 4 data rows, fewer than 3 distinct angles.
TorqueTable read_torque_table(const std::string& path);

/// The column roles of a torque table (angle, torque, time, sweep, torque_se) with their
/// default headers, for --column and --unit (estimators/lab_table.h).
const std::vector<ColumnRole>& torque_table_roles();

/// Reads a lab's table as it comes (estimators/lab_table.h: any delimiter, comments, headers
/// with spaces and units, the columns named by `mapping`), into the same TorqueTable; the
/// torque "as written" is in the unit its column was read in. A file with the default comma
/// format and an empty mapping is read by read_torque_table(path), with its messages. Throws as
/// read_lab_table does, and as read_torque_table for too few rows or distinct angles, a torque
/// beyond 1e9 N*m, a sweep other than +1/-1.
TorqueTable read_torque_table(const std::string& path, const ColumnMapping& mapping);

/// At least 4 rows and 3 distinct angles (modulo 360 deg); throws poise::Error naming the file.
void check_torque_table(const std::string& path, const TorqueTable& t);

}  // namespace poise::estimators
