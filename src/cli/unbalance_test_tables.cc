#include "cli/unbalance_test_tables.h"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "core/error.h"

namespace poise::cli {
namespace {

constexpr double kRadPerDeg = 3.141592653589793 / 180.0;

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r\xEF\xBB\xBF");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  std::string c;
  while (std::getline(ss, c, ',')) cells.push_back(trim(c));
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

// The header's columns, and which tests the file holds.
struct TableColumns {
  std::size_t count = 0;                   ///< cells per row
  std::map<std::string, std::size_t> col;  ///< column name -> index
  bool loading = false;                    ///< loading tests (circle) or repeatability (points)
  bool printed = false;                    ///< printed error columns to check
};

TableColumns read_header(const std::string& path, const std::string& line) {
  const std::vector<std::string> header = split(line);
  TableColumns c;
  c.count = header.size();
  for (std::size_t i = 0; i < header.size(); ++i) c.col[header[i]] = i;
  for (const char* need : {"load_angle_deg", "load_torque_mNm", "measured_torque_mNm", "measured_angle_deg"}) {
    if (!c.col.count(need)) throw Error(path + ":1: no column '" + need + "' (expected it in the header)");
  }
  c.loading = c.col.count("circle") > 0;
  if (!c.loading && !c.col.count("points")) {
    throw Error(path + ":1: neither 'circle' (loading tests) nor 'points' (repeatability tests) in the header");
  }
  c.printed = c.col.count("printed_torque_error_mNm") && c.col.count("printed_angle_error_deg");
  return c;
}

// One data row: its cells, and where it is (for the messages).
struct TableRow {
  const TableColumns& columns;
  const std::vector<std::string>& cells;
  std::string at;  ///< "path:line"

  const std::string& cell(const std::string& name) const { return cells[columns.col.at(name)]; }
  bool has(const std::string& name) const { return columns.col.count(name) > 0; }
  double number(const std::string& name) const {
    const std::string& s = cell(name);
    std::size_t used = 0;
    double v = NAN;
    try {
      v = std::stod(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != s.size() || s.empty() || !std::isfinite(v)) {
      throw Error(at + ": column " + name + ": '" + s + "' (expected a finite number)");
    }
    return v;
  }
};

// Which table and test a row is (the row-th data row), and its positions.
estimators::UnbalanceTestRecord identify_test(const TableRow& r, int row) {
  estimators::UnbalanceTestRecord t;
  if (r.columns.loading) {
    const std::string circle = r.cell("circle");
    if (circle != "C_A" && circle != "C_B")
      throw Error(r.at + ": column circle: '" + circle + "' (expected C_A or C_B)");
    t.table = circle == "C_A" ? "Table 2" : "Table 3";
    t.number = r.has("test") ? static_cast<int>(r.number("test")) : row;
    t.positions = r.has("points") ? static_cast<int>(r.number("points")) : 36;
  } else {
    t.positions = static_cast<int>(r.number("points"));
    if (t.positions != 36 && t.positions != 18) {
      throw Error(r.at + ": column points: " + r.cell("points") + " (expected 36 (Table 4) or 18 (Table 5))");
    }
    t.table = t.positions == 36 ? "Table 4" : "Table 5";
    t.number = r.has("repeat") ? static_cast<int>(r.number("repeat")) : row;
  }
  if (t.positions < 4) throw Error(r.at + ": " + std::to_string(t.positions) + " positions (expected at least 4)");
  return t;
}

// A row's load and measurement as written (mN*m, deg).
struct RowFigures {
  double load_mNm = 0, load_deg = 0, meas_mNm = 0, meas_deg = 0;
};

// The printed errors: each row's against measured - load, and their RMS per table.
struct PrintedErrors {
  std::map<std::string, std::pair<double, double>> sums;  // table -> printed squared sums
  std::map<std::string, int> counts;
  std::vector<std::string> order;

  void check(const TableRow& r, const estimators::UnbalanceTestRecord& t, const RowFigures& f,
             UnbalanceTestData& data) {
    const double pt = r.number("printed_torque_error_mNm"), pa = r.number("printed_angle_error_deg");
    const double rt = f.meas_mNm - f.load_mNm, ra = std::remainder(f.meas_deg - f.load_deg, 360.0);
    if (std::abs(pt - rt) > 0.006) data.mismatches.push_back({t.table, t.number, "printed_torque_error_mNm", pt, rt});
    if (std::abs(pa - ra) > 0.006) data.mismatches.push_back({t.table, t.number, "printed_angle_error_deg", pa, ra});
    if (!counts.count(t.table)) order.push_back(t.table);
    sums[t.table].first += pt * pt;
    sums[t.table].second += pa * pa;
    ++counts[t.table];
  }

  void write_rmse(UnbalanceTestData& data) {
    for (const auto& name : order) {
      const double n = counts[name];
      data.printed_rmse.push_back({name, std::sqrt(sums[name].first / n), std::sqrt(sums[name].second / n)});
    }
  }
};

}  // namespace

void read_unbalance_tests(const std::string& path, UnbalanceTestData& data) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot be read (expected a CSV file of measured unbalance tests)");
  std::string line;
  std::size_t line_no = 1;
  if (!std::getline(in, line)) throw Error(path + ": empty file (expected a header line)");
  const TableColumns columns = read_header(path, line);
  PrintedErrors printed;
  int row = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (trim(line).empty()) continue;
    const std::vector<std::string> cells = split(line);
    const TableRow r{columns, cells, path + ":" + std::to_string(line_no)};
    if (cells.size() != columns.count) {
      throw Error(r.at + ": " + std::to_string(cells.size()) + " cells (expected " + std::to_string(columns.count) +
                  ", as in the header)");
    }
    ++row;
    estimators::UnbalanceTestRecord t = identify_test(r, row);
    RowFigures f;
    f.load_mNm = r.number("load_torque_mNm");
    f.load_deg = r.number("load_angle_deg");
    f.meas_mNm = r.number("measured_torque_mNm");
    f.meas_deg = r.number("measured_angle_deg");
    if (!(f.load_mNm > 0))
      throw Error(r.at + ": column load_torque_mNm: " + r.cell("load_torque_mNm") + " (expected > 0)");
    t.load_torque = f.load_mNm * 1e-3;
    t.load_angle = f.load_deg * kRadPerDeg;
    t.torque = f.meas_mNm * 1e-3;
    t.angle = f.meas_deg * kRadPerDeg;
    if (columns.printed) printed.check(r, t, f, data);
    data.tests.push_back(t);
  }
  if (row == 0) throw Error(path + ": no data rows (expected one row per test)");
  printed.write_rmse(data);
}

}  // namespace poise::cli
