// read_torque_table of a lab's file as it comes (torque_table.h).
#include <cmath>
#include <fstream>

#include "core/error.h"
#include "core/format.h"
#include "estimators/torque_table.h"

namespace poise::estimators {
namespace {

// The default format: its first line that is not blank names the columns, comma-separated, no
// comment before it.
bool default_format(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    return line.find(',') != std::string::npos && line.find(';') == std::string::npos &&
           line.find('\t') == std::string::npos && line[line.find_first_not_of(" \t")] != '#' &&
           line[line.find_first_not_of(" \t")] != '%';
  }
  return true;
}

}  // namespace

const std::vector<ColumnRole>& torque_table_roles() {
  static const std::vector<ColumnRole> roles = {
      {"angle", {"theta_deg"}, units::kAngle, "deg", true, "turntable angle"},
      {"torque", {"torque_mNm"}, units::kTorque, "mN*m", true, "unbalance torque"},
      {"time", {"time_s"}, units::kTime, "s", false, "time of the measurement"},
      {"sweep", {"sweep"}, units::kDimensionless, "1", false, "turntable direction (+1 or -1)"},
      {"torque_se", {"torque_se_mNm"}, units::kTorque, "mN*m", false, "standard error of the torque"},
  };
  return roles;
}

TorqueTable read_torque_table(const std::string& path, const ColumnMapping& mapping) {
  if (mapping.header.empty() && mapping.unit.empty() && default_format(path)) return read_torque_table(path);
  const LabTable lab = read_lab_table(path, torque_table_roles(), mapping);
  TorqueTable t;
  t.file = path;
  t.torque_column = lab.header.at("torque");
  t.unit = lab.unit.at("torque");
  t.unit_factor = column_unit_factor(t.unit, units::kTorque);
  t.rows = lab.lines;
  t.theta_rad = lab.at("angle");
  t.torque_Nm = lab.at("torque");
  for (std::size_t k = 0; k < lab.size(); ++k) {
    t.theta_deg.push_back(t.theta_rad[k] / units::kRadPerDeg);
    t.torque.push_back(t.torque_Nm[k] / t.unit_factor);
    if (!(std::abs(t.torque_Nm[k]) <= 1e9)) {
      throw Error(fmt::format("{}:{}: column '{}': {} N*m; expected a torque of at most 1e9 N*m in magnitude", path,
                              lab.lines[k], t.torque_column, significant(t.torque_Nm[k], 6)));
    }
  }
  if (lab.has("time")) t.time_s = lab.at("time");
  if (lab.has("sweep")) {
    for (std::size_t k = 0; k < lab.size(); ++k) {
      const double s = lab.at("sweep")[k];
      if (s != 1.0 && s != -1.0) {
        throw Error(fmt::format("{}:{}: column '{}': {}; expected +1 or -1 (turntable direction)", path, lab.lines[k],
                                lab.header.at("sweep"), significant(s, 6)));
      }
      t.sweep.push_back(s > 0 ? 1 : -1);
    }
  }
  if (lab.has("torque_se")) {
    for (const double se : lab.at("torque_se")) {
      require(se > 0.0 && se <= 1e9,
              path + ": column '" + lab.header.at("torque_se") + "': expected standard errors > 0 and at most 1e9 N*m");
      t.torque_se.push_back(se / t.unit_factor);
    }
  }
  check_torque_table(path, t);
  return t;
}

}  // namespace poise::estimators
