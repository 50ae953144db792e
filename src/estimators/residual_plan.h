#pragma once
/// Internal to residual_diagnosis.cc: the test plan as the data show it (positions, repeats,
/// directions, and whether time order follows angle order, which confounds every smooth
/// function of time with one of angle).
#include <cstddef>
#include <string>
#include <vector>

#include "estimators/torque_table.h"

namespace poise::estimators::detail {

/// Spearman rank correlation of the angle with the measurement order.
double order_angle_correlation(const TorqueTable& table, const std::vector<std::size_t>& order);

/// |order_angle_correlation| > 0.95: a one-direction sweep, time order follows angle order.
bool monotone_plan(const TorqueTable& table, const std::vector<std::size_t>& order);

/// One line: points, positions, repeats, directions, order source and the rank correlation.
std::string describe_plan(const TorqueTable& table, const std::vector<std::size_t>& order, bool monotone);

}  // namespace poise::estimators::detail
