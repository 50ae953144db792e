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

}  // namespace

void read_unbalance_tests(const std::string& path, UnbalanceTestData& data) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot be read (expected a CSV file of measured unbalance tests)");
  std::string line;
  std::size_t line_no = 1;
  if (!std::getline(in, line)) throw Error(path + ": empty file (expected a header line)");
  const std::vector<std::string> header = split(line);
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
  for (const char* need : {"load_angle_deg", "load_torque_mNm", "measured_torque_mNm", "measured_angle_deg"}) {
    if (!col.count(need)) throw Error(path + ":1: no column '" + need + "' (expected it in the header)");
  }
  const bool loading = col.count("circle") > 0;
  if (!loading && !col.count("points")) {
    throw Error(path + ":1: neither 'circle' (loading tests) nor 'points' (repeatability tests) in the header");
  }
  const bool printed = col.count("printed_torque_error_mNm") && col.count("printed_angle_error_deg");
  std::map<std::string, std::pair<double, double>> sums;  // table -> printed squared sums
  std::map<std::string, int> counts;
  std::vector<std::string> order;
  int row = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (trim(line).empty()) continue;
    const std::vector<std::string> cells = split(line);
    const std::string at = path + ":" + std::to_string(line_no);
    if (cells.size() != header.size()) {
      throw Error(at + ": " + std::to_string(cells.size()) + " cells (expected " + std::to_string(header.size()) +
                  ", as in the header)");
    }
    auto number = [&](const std::string& name) {
      const std::string& s = cells[col.at(name)];
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
    };
    estimators::UnbalanceTestRecord t;
    ++row;
    if (loading) {
      const std::string circle = cells[col.at("circle")];
      if (circle != "C_A" && circle != "C_B") throw Error(at + ": column circle: '" + circle + "' (expected C_A or C_B)");
      t.table = circle == "C_A" ? "Table 2" : "Table 3";
      t.number = col.count("test") ? static_cast<int>(number("test")) : row;
      t.positions = col.count("points") ? static_cast<int>(number("points")) : 36;
    } else {
      t.positions = static_cast<int>(number("points"));
      if (t.positions != 36 && t.positions != 18) {
        throw Error(at + ": column points: " + cells[col.at("points")] + " (expected 36 (Table 4) or 18 (Table 5))");
      }
      t.table = t.positions == 36 ? "Table 4" : "Table 5";
      t.number = col.count("repeat") ? static_cast<int>(number("repeat")) : row;
    }
    if (t.positions < 4) throw Error(at + ": " + std::to_string(t.positions) + " positions (expected at least 4)");
    const double load_mNm = number("load_torque_mNm"), load_deg = number("load_angle_deg");
    const double meas_mNm = number("measured_torque_mNm"), meas_deg = number("measured_angle_deg");
    if (!(load_mNm > 0)) throw Error(at + ": column load_torque_mNm: " + cells[col.at("load_torque_mNm")] + " (expected > 0)");
    t.load_torque = load_mNm * 1e-3;
    t.load_angle = load_deg * kRadPerDeg;
    t.torque = meas_mNm * 1e-3;
    t.angle = meas_deg * kRadPerDeg;
    if (printed) {
      const double pt = number("printed_torque_error_mNm"), pa = number("printed_angle_error_deg");
      const double rt = meas_mNm - load_mNm, ra = std::remainder(meas_deg - load_deg, 360.0);
      if (std::abs(pt - rt) > 0.006) data.mismatches.push_back({t.table, t.number, "printed_torque_error_mNm", pt, rt});
      if (std::abs(pa - ra) > 0.006) data.mismatches.push_back({t.table, t.number, "printed_angle_error_deg", pa, ra});
      if (!counts.count(t.table)) order.push_back(t.table);
      sums[t.table].first += pt * pt;
      sums[t.table].second += pa * pa;
      ++counts[t.table];
    }
    data.tests.push_back(t);
  }
  if (row == 0) throw Error(path + ": no data rows (expected one row per test)");
  for (const auto& name : order) {
    const double n = counts[name];
    data.printed_rmse.push_back({name, std::sqrt(sums[name].first / n), std::sqrt(sums[name].second / n)});
  }
}

}  // namespace poise::cli
