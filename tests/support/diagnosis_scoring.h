#pragma once
// Test helper shared by the diagnosis tests on independently generated data
// (tests/support/independent_gimbal_data.h): a generated table as the TorqueTable Poise reads.
#include <cstddef>
#include <numbers>

#include "estimators/torque_table.h"
#include "independent_gimbal_data.h"

namespace poise::estimators::scoring {

inline TorqueTable to_table(const testdata::Table& t) {
  TorqueTable out;
  out.file = "independent.csv";
  out.torque_column = "torque_mNm";
  out.unit = "mN*m";
  out.unit_factor = 1e-3;
  for (std::size_t i = 0; i < t.theta_deg.size(); ++i) {
    out.theta_deg.push_back(t.theta_deg[i]);
    out.theta_rad.push_back(t.theta_deg[i] * std::numbers::pi / 180.0);
    out.torque.push_back(t.torque_mNm[i]);
    out.torque_Nm.push_back(t.torque_mNm[i] * 1e-3);
    out.rows.push_back(i + 2);
  }
  out.time_s = t.time_s;
  out.sweep = t.sweep;
  return out;
}

}  // namespace poise::estimators::scoring
