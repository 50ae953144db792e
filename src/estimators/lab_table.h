#pragma once
/// A lab's text table as it comes: the columns a command needs, found by role, converted to SI.
/// The one reader of measured files with columns (raw records of `poise diagnose-record`,
/// torque tables of `poise fit` and `poise diagnose`).
///
/// What it accepts, so that a logger's file needs no editing:
/// - delimiters: comma, semicolon, tab, or runs of spaces; found from the header line (the
///   most frequent of ';', tab and ','; none of them: whitespace). With ';' or tab as the
///   delimiter, a decimal comma ("0,25") is read as a decimal point;
/// - comment lines starting with '#', '%' or "//" anywhere, and blank lines; a UTF-8 byte
///   order mark; CRLF line ends; cells and headers with spaces around them, or in double quotes
///   (which may hold the delimiter, "Iq, A", and "" for a quote); numbers with a leading '+';
/// - a time column of dates and times ("2024-07-04 11:34:18.818", "2024-07-04T11:34:18Z", an
///   offset "+02:00" taken off): seconds since 1970-01-01 UTC (only differences matter);
/// - the header: the first line that is not a comment. A column is found by its role: by the
///   header the user names (`--column current=Iq`), else by the role's default headers.
/// - units: `--unit ROLE=UNIT` with any unit Poise knows of the role's dimension ("ms", "mA",
///   "rad", "rev"), a quantity for one count ("0.0219726 deg"), or a fraction of one
///   ("1/16384 rev": encoder counts); without it, the unit in the header ("time [ms]",
///   "Iq (A)", "position_rad": in brackets or parentheses, or after the last '_'); else the
///   role's default unit if its header is a default one. A column whose unit is not known is
///   an error naming the column and the option that gives it.
/// - a NumPy .npy array (float64, float32, int64 or int32): its series are the columns, named
///   "0", "1", ... (a 2-D array of shape (a, b) holds min(a, b) series), so each role is named
///   with --column ROLE=INDEX and its unit with --unit.
/// Every error names the file, the line, the column and the cell, and what was expected.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "core/units.h"

namespace poise::estimators {

/// One column a reader needs.
struct ColumnRole {
  std::string role;                          ///< "time", "current", "angle", ... (the --column key)
  std::vector<std::string> default_headers;  ///< headers that name it without --column
  units::Dimension dimension;                ///< what its values are
  std::string default_unit;                  ///< the unit of a default header ("s", "A", "deg")
  bool required = true;
  std::string what;   ///< "time", "drive current", ...: for messages
  bool text = false;  ///< cells kept as written (a sensor's name), no unit
  /// A header the user named without a unit in it is in default_unit (a file whose units a
  /// campaign declares), instead of an error asking for --unit.
  bool unit_by_default = false;
};

/// What the user said of the file's columns: role -> header (--column), role -> unit (--unit).
struct ColumnMapping {
  std::map<std::string, std::string> header;
  std::map<std::string, std::string> unit;
  /// How the user names a column, for messages ("" = the command line's --column ROLE=HEADER;
  /// a campaign file says its own keys).
  std::string naming = "";
};

/// Parses "ROLE=VALUE" options into a mapping (throws poise::InputError naming the option for
/// a malformed one or a role not in `roles`).
void add_column_option(ColumnMapping& mapping, const std::string& option, const std::string& text,
                       const std::vector<ColumnRole>& roles);

/// The columns found, each in SI (angles in rad), in file order.
struct LabTable {
  std::string file;
  std::map<std::string, std::vector<double>> si;         ///< role -> values (only the roles found)
  std::map<std::string, std::vector<std::string>> text;  ///< role -> cells of a text role
  std::map<std::string, std::string> header;             ///< role -> the header that held it
  std::map<std::string, std::string> unit;               ///< role -> the unit read (as written)
  std::vector<std::size_t> lines;                        ///< file line (1-based) of each row
  std::string delimiter;                                 ///< "comma", "semicolon", "tab", "whitespace"
  std::size_t header_line = 1;

  bool has(const std::string& role) const { return si.count(role) > 0; }
  const std::vector<double>& at(const std::string& role) const { return si.at(role); }
  std::size_t size() const { return lines.size(); }
};

/// Reads the file (format above). Throws poise::InputError (file, line, column, cell, what was
/// expected) for a cell that is not a finite number, a row with too few cells, a header the
/// user named that the file lacks (with the headers it has), a column whose unit is unknown or
/// of another dimension; poise::Error ("file:line: ...") for a file that cannot be read or
/// holds no header, a missing required column (with the headers the file has), a row with more
/// cells than the header.
LabTable read_lab_table(const std::string& path, const std::vector<ColumnRole>& roles, const ColumnMapping& mapping);

/// SI value of one unit of a column: "ms", "0.5 deg", "1/4096 rev". Throws poise::Error saying
/// what was expected for a text that is none of these or of another dimension than `dim`.
double column_unit_factor(const std::string& text, const units::Dimension& dim);

}  // namespace poise::estimators
