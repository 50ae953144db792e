#include "estimators/torque_table.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>
#include <optional>
#include <string_view>

#include "core/error.h"
#include "estimators/sine_fit.h"

namespace poise::estimators {
namespace {

constexpr std::size_t kMinRows = 4;
// Largest torque (and standard error) a table may hold, N*m: no measured unbalance torque is
// within orders of magnitude of it, and far larger values overflow the sums of squares of the
// fits (1e308 mN*m gave a NaN statistic and a Boost.Math error in `poise diagnose`, issue 20).
constexpr double kMaxTorqueNm = 1e9;

std::string_view trim(std::string_view s) {
  const auto is_space = [](char ch) { return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\v' || ch == '\f'; };
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split_cells(std::string_view line) {
  std::vector<std::string_view> cells;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    cells.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) return cells;
    start = comma + 1;
  }
}

template <class Cells>  // vector of string or string_view
std::string join(const Cells& cells) {
  std::string out;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    out.append(i ? "," : "").append(std::string_view(cells[i]));
  }
  return out;
}

// Errors read "<file>:<line>: <what>", the form compilers use, so editors can jump to them.
[[noreturn]] void fail(const std::string& file, std::size_t line, const std::string& what) {
  throw Error(file + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + what);
}

// A finite number filling the whole cell (a leading '+' is allowed), else nullopt.
std::optional<double> parse_number(std::string_view cell) {
  if (cell.size() > 1 && cell.front() == '+' && cell[1] != '-' && cell[1] != '+') {
    cell.remove_prefix(1);
  }
  double v = 0.0;
  const auto [end, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
  if (ec != std::errc() || end != cell.data() + cell.size() || !std::isfinite(v)) {
    return std::nullopt;
  }
  return v;
}

struct Columns {
  std::vector<std::string> names;
  std::size_t theta = 0, torque = 0;
  std::optional<std::size_t> time, sweep, se;
  double se_factor = 1.0;  // file unit of the se column in the table's torque unit
};

Columns find_columns(const std::string& file, std::size_t line, const std::vector<std::string_view>& header,
                     TorqueTable& t) {
  const std::string where = "header '" + join(header) + "'";
  Columns c;
  c.names.assign(header.begin(), header.end());
  std::optional<std::size_t> theta, mnm, nm, se_mnm, se_nm;
  for (std::size_t i = 0; i < header.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (!header[i].empty() && header[i] == header[j]) {
        fail(file, line, where + ": column '" + std::string(header[i]) + "' appears twice");
      }
    }
    if (header[i] == "theta_deg") theta = i;
    if (header[i] == "torque_mNm") mnm = i;
    if (header[i] == "torque_Nm") nm = i;
    if (header[i] == "time_s") c.time = i;
    if (header[i] == "sweep") c.sweep = i;
    if (header[i] == "torque_se_mNm") se_mnm = i;
    if (header[i] == "torque_se_Nm") se_nm = i;
  }
  if (se_mnm && se_nm) {
    fail(file, line, where + ": two columns 'torque_se_mNm' and 'torque_se_Nm'; expected at most one");
  }
  if (!theta) {
    fail(file, line, where + ": no column 'theta_deg'; expected the turntable angle in degrees");
  }
  if (mnm && nm) {
    fail(file, line, where + ": two torque columns 'torque_mNm' and 'torque_Nm'; expected exactly one");
  }
  if (!mnm && !nm) {
    fail(file, line, where + ": no torque column; expected 'torque_mNm' (mN*m) or 'torque_Nm' (N*m)");
  }
  c.theta = *theta;
  c.torque = mnm ? *mnm : *nm;
  t.torque_column = mnm ? "torque_mNm" : "torque_Nm";
  t.unit = mnm ? "mN*m" : "N*m";
  t.unit_factor = mnm ? 1e-3 : 1.0;
  if (se_mnm || se_nm) {
    c.se = se_mnm ? *se_mnm : *se_nm;
    c.se_factor = (se_mnm ? 1e-3 : 1.0) / t.unit_factor;
  }
  return c;
}

// One data row's cells into the table (every cell checked: a number, in range).
void read_row(const std::string& path, std::size_t line, const std::vector<std::string_view>& cells,
              const Columns& cols, TorqueTable& t) {
  if (cells.size() != cols.names.size()) {
    fail(path, line,
         "row '" + join(cells) + "' has " + std::to_string(cells.size()) + (cells.size() == 1 ? " cell" : " cells") +
             " but the header has " + std::to_string(cols.names.size()) + " columns '" + join(cols.names) + "'");
  }
  const auto number = [&](std::size_t col) {
    const std::string& name = cols.names[col];
    if (cells[col].empty()) fail(path, line, "column '" + name + "': empty cell; expected a number");
    const auto v = parse_number(cells[col]);
    if (!v) fail(path, line, "column '" + name + "': cell '" + std::string(cells[col]) + "' is not a finite number");
    return *v;
  };
  const double theta = number(cols.theta);
  const double torque = number(cols.torque);
  if (!(std::abs(torque * t.unit_factor) <= kMaxTorqueNm)) {
    fail(path, line,
         "column '" + cols.names[cols.torque] + "': cell '" + std::string(cells[cols.torque]) +
             "'; expected a torque of at most 1e9 N*m in magnitude");
  }
  t.theta_deg.push_back(theta);
  t.theta_rad.push_back(theta * (std::numbers::pi / 180.0));
  t.torque.push_back(torque);
  t.torque_Nm.push_back(torque * t.unit_factor);
  t.rows.push_back(line);
  if (cols.time) t.time_s.push_back(number(*cols.time));
  if (cols.se) {
    const double se = number(*cols.se);
    if (!(se > 0.0) || !(se * cols.se_factor * t.unit_factor <= kMaxTorqueNm)) {
      fail(path, line,
           "column '" + cols.names[*cols.se] + "': cell '" + std::string(cells[*cols.se]) +
               "'; expected a standard error > 0 and at most 1e9 N*m (the scatter of the "
               "position's period integrals / sqrt(periods))");
    }
    t.torque_se.push_back(se * cols.se_factor);
  }
  if (cols.sweep) {
    const double sw = number(*cols.sweep);
    if (sw != 1.0 && sw != -1.0) {
      fail(path, line,
           "column 'sweep': cell '" + std::string(cells[*cols.sweep]) + "'; expected +1 or -1 (turntable direction)");
    }
    t.sweep.push_back(sw > 0.0 ? 1 : -1);
  }
}

}  // namespace

void check_torque_table(const std::string& path, const TorqueTable& t) {
  if (t.size() < kMinRows) {
    fail(path, 0,
         std::to_string(t.size()) + " data rows; expected at least " + std::to_string(kMinRows) +
             " (the sine fit has 3 parameters)");
  }
  const std::size_t distinct = count_distinct_angles(t.theta_rad);
  if (distinct < 3) {
    fail(path, 0,
         "duplicate angles only: " + std::to_string(distinct) + " distinct value(s) of theta_deg modulo 360 deg in " +
             std::to_string(t.size()) + " rows; expected at least 3");
  }
}

namespace {

// The whole table: a header, enough rows, at least 3 distinct angles.
void check_table(const std::string& path, const std::optional<Columns>& cols, const TorqueTable& t) {
  if (!cols) fail(path, 0, "no header line; expected e.g. 'theta_deg,torque_mNm'");
  check_torque_table(path, t);
}

}  // namespace

TorqueTable read_torque_table(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, 0, "cannot open the file for reading");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string_view rest(text);
  if (rest.starts_with("\xEF\xBB\xBF")) rest.remove_prefix(3);  // UTF-8 BOM from spreadsheets

  TorqueTable t;
  t.file = path;
  std::optional<Columns> cols;
  std::size_t line = 0;
  while (!rest.empty()) {
    const std::size_t nl = rest.find('\n');
    const std::string_view raw = rest.substr(0, nl);
    rest.remove_prefix(nl == std::string_view::npos ? rest.size() : nl + 1);
    ++line;
    if (trim(raw).empty()) continue;  // blank lines carry no data
    const std::vector<std::string_view> cells = split_cells(raw);
    if (!cols) {
      cols = find_columns(path, line, cells, t);
    } else {
      read_row(path, line, cells, *cols, t);
    }
  }
  check_table(path, cols, t);
  return t;
}

}  // namespace poise::estimators
