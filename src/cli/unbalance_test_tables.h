#pragma once
/// Measured static-unbalance tests read from CSV for `poise error-mechanisms`: each row a test
/// that was given a known load and measured it (the format of data/yang2015/):
///   loading tests (tables2_3_loading_tests.csv):   test, circle, load_angle_deg,
///       load_torque_mNm, measured_torque_mNm, measured_angle_deg; the table of a row is
///       "Table 2" for circle C_A and "Table 3" for C_B; 36 positions each (column
///       `points` if present);
///   repeatability tests (tables4_5_repeatability.csv): points, repeat, the same four
///       columns; "Table 4" for 36 points, "Table 5" for 18.
/// Optional columns printed_torque_error_mNm and printed_angle_error_deg hold the error rows
/// as the paper prints them: each is checked against measured - load, and a row whose
/// printed error differs by more than the rounding (0.006) is reported, not corrected.
#include <string>
#include <vector>

#include "estimators/error_mechanism_likelihood.h"

namespace poise::cli {

/// A printed error that its own row does not give.
struct PrintedErrorMismatch {
  std::string table;
  int number = 0;
  std::string column;       ///< printed_torque_error_mNm or printed_angle_error_deg
  double printed = 0.0;     ///< as printed (mN*m or deg)
  double recomputed = 0.0;  ///< measured - load from the same row
};

struct UnbalanceTestData {
  std::vector<estimators::UnbalanceTestRecord> tests;  ///< in file order
  std::vector<PrintedErrorMismatch> mismatches;
  /// Per table: RMS of the printed torque and angle errors (NaN without the columns).
  struct PrintedRmse {
    std::string table;
    double torque_mNm = 0.0, angle_deg = 0.0;
  };
  std::vector<PrintedRmse> printed_rmse;
};

/// Reads a loading-test or repeatability file (which one from its columns) and appends its
/// rows to `data`. Throws poise::Error naming the file, line, column and cell for a file that
/// cannot be read, a missing column, a row of the wrong length, a cell that is not a finite
/// number, a circle other than C_A / C_B, points other than 18 or 36 without a circle, a load
/// torque <= 0.
void read_unbalance_tests(const std::string& path, UnbalanceTestData& data);

}  // namespace poise::cli
