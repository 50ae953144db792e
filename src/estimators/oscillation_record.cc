#include "estimators/oscillation_record.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "core/units.h"

namespace poise::estimators {
namespace {

std::vector<std::string> split_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();  // a trailing empty cell
  return cells;
}

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\r' || s.back() == ' ' || s.back() == '\t')) s.pop_back();
  std::size_t b = 0;
  while (b < s.size() && (s[b] == ' ' || s[b] == '\t')) ++b;
  return s.substr(b);
}

}  // namespace

OscillationRecord read_oscillation_record(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open the file");
  std::string line;
  std::getline(in, line);
  if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark
  std::vector<std::string> head = split_cells(line);
  for (auto& h : head) h = trimmed(h);
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < head.size(); ++i) col.emplace(head[i], i);
  for (const char* need : {"time_s", "current_A", "phi_deg"}) {
    if (!col.count(need)) {
      throw Error(path + ":1: missing column '" + need + "' (need time_s, current_A, phi_deg)");
    }
  }
  OscillationRecord r;
  r.file = path;
  std::size_t lineno = 1;
  while (std::getline(in, line)) {
    ++lineno;
    if (trimmed(line).empty()) continue;
    const std::vector<std::string> cells = split_cells(line);
    if (cells.size() != head.size()) {
      throw Error(path + ":" + std::to_string(lineno) + ": " + std::to_string(cells.size()) +
                  " cells, the header has " + std::to_string(head.size()));
    }
    auto num = [&](const char* name) {
      const std::string c = trimmed(cells[col.at(name)]);
      const std::size_t sign = !c.empty() && c[0] == '+' ? 1 : 0;  // "+0.5" as written by some loggers
      double v = 0.0;
      const auto res = std::from_chars(c.data() + sign, c.data() + c.size(), v);
      const bool whole =
          c.size() > sign && !(sign && c[1] == '-') && res.ec == std::errc() && res.ptr == c.data() + c.size();
      if (!whole || !std::isfinite(v)) {
        throw InputError({path, static_cast<int>(std::min<std::size_t>(lineno, 2147483647u)), 0},
                         std::string("column ") + name, c.empty() ? "(empty)" : c, "a finite number");
      }
      return v;
    };
    r.t.push_back(num("time_s"));
    r.current.push_back(num("current_A"));
    r.phi.push_back(num("phi_deg") * units::kRadPerDeg);
    r.lines.push_back(lineno);
  }
  return r;
}

}  // namespace poise::estimators
