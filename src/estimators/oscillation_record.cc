#include "estimators/oscillation_record.h"

#include <cmath>

#include "core/error.h"
#include "core/format.h"

namespace poise::estimators {

const std::vector<ColumnRole>& record_column_roles() {
  static const std::vector<ColumnRole> roles = {
      {"time", {"time_s"}, units::kTime, "s", false, "time"},
      {"current", {"current_A"}, units::kCurrent, "A", false, "drive current"},
      {"torque", {"torque_Nm"}, units::kTorque, "N*m", false, "drive torque"},
      {"angle", {"phi_deg"}, units::kAngle, "deg", true, "axis angle"},
      {"velocity", {"velocity_rad_s"}, units::Dimension{{0, 0, -1, 0, 1, 0}}, "rad/s", false, "angular velocity"},
  };
  return roles;
}

OscillationRecord read_oscillation_record(const std::string& path, const ColumnMapping& mapping) {
  const LabTable t = read_lab_table(path, record_column_roles(), mapping);
  OscillationRecord r;
  r.file = path;
  r.lines = t.lines;
  if (t.has("time")) {
    r.t = t.at("time");
  } else {  // a map without time: the rows in their order
    r.no_time = true;
    for (std::size_t k = 0; k < t.size(); ++k) r.t.push_back(static_cast<double>(k));
    r.notes.push_back("no time column: the rows are taken in their order, as a quasi-static map");
  }
  r.phi = t.at("angle");
  if (t.has("torque") && (mapping.header.count("torque") || !t.has("current"))) {
    r.torque = t.at("torque");
  } else if (t.has("current")) {
    r.current = t.at("current");
  } else {
    throw InputError({path, static_cast<int>(t.header_line), 0}, "column of the drive current or torque", "(none)",
                     "a column 'current_A' or 'torque_Nm', or name one with --column current=HEADER "
                     "or --column torque=HEADER");
  }
  if (t.has("velocity")) r.velocity = t.at("velocity");
  r.notes.push_back(fmt::format("{} rows read, delimited by {}", t.size(), t.delimiter));
  for (const auto& [role, header] : t.header) {
    if (role == "current" && !r.torque.empty()) continue;
    if (role == "torque" && r.torque.empty()) continue;
    r.notes.push_back(fmt::format("{}: column '{}' in {}", role, header, t.unit.at(role)));
  }
  // A single-turn encoder wraps: a jump of more than half a turn between two rows is a wrap.
  std::size_t unwraps = 0;
  double shift = 0.0;
  for (std::size_t k = 1; k < r.phi.size(); ++k) {
    const double raw_step = r.phi[k] + shift - r.phi[k - 1];
    if (std::abs(raw_step) > units::kPi) {
      shift -= 2.0 * units::kPi * std::round(raw_step / (2.0 * units::kPi));
      ++unwraps;
    }
    r.phi[k] += shift;
  }
  if (unwraps > 0) {
    r.notes.push_back(fmt::format(
        "the angle wraps {} time(s) (a jump of more than half a turn between two rows): unwrapped", unwraps));
  }
  return r;
}

}  // namespace poise::estimators
