#pragma once
/// The tolerance slots of the balancing-machine study: one per drawn quantity (a plate
/// tolerance is drawn for each of the three plates), with its input column, model key and
/// scope rule. Shared by the study's construction (balancing_study_setup.cc) and its samples
/// (balancing_study.cc); not a public interface.
#include <cstddef>
#include <string>

#include "kinds/balancing_machine/balancing_model.h"

namespace poise::kinds::balancing_machine::detail {

enum Slot : std::size_t {
  kThicknessH1,
  kThicknessH2,
  kThicknessT,
  kWidthH1,
  kWidthH2,
  kWidthT,
  kLengthH1,
  kLengthH2,
  kLengthT,
  kYoungs,
  kLever,
  kSensor1,
  kPiece,
  kGain1,
  kGain2,
  kResidual1,
  kResidual2,
  kSpeed,
  kTestMass,
  kHoleRadius,
  kHoleAngle,
  kCorrMass,
  kCorrAngle,
  kSlotCount
};

struct SlotSpec {
  const char* name;  // input column
  const char* key;   // tolerance key in the model file
  const ScopedTolerance BalancingModel::*tol;
  bool magnitude;  // a magnitude with a uniform angle (two design dimensions)
  bool hardware;   // must be scope "unit" (a property of the machine as built)
};

inline const SlotSpec kSlots[kSlotCount] = {
    {"horizontal_1_thickness", "plate_thickness", &BalancingModel::plate_thickness, false, true},
    {"horizontal_2_thickness", "plate_thickness", &BalancingModel::plate_thickness, false, true},
    {"torsional_thickness", "plate_thickness", &BalancingModel::plate_thickness, false, true},
    {"horizontal_1_width", "plate_width", &BalancingModel::plate_width, false, true},
    {"horizontal_2_width", "plate_width", &BalancingModel::plate_width, false, true},
    {"torsional_width", "plate_width", &BalancingModel::plate_width, false, true},
    {"horizontal_1_length", "plate_length", &BalancingModel::plate_length, false, true},
    {"horizontal_2_length", "plate_length", &BalancingModel::plate_length, false, true},
    {"torsional_length", "plate_length", &BalancingModel::plate_length, false, true},
    {"youngs_modulus", "youngs_modulus", &BalancingModel::youngs_modulus, false, true},
    {"lever", "lever", &BalancingModel::lever_error, false, true},
    {"sensor_1_offset", "sensor_1_offset", &BalancingModel::sensor_1_offset, false, true},
    {"piece_centre_height", "piece_centre_height", &BalancingModel::piece_centre_height, false, true},
    {"gain_error_1", "gain_error_1", &BalancingModel::gain_error_1, false, true},
    {"gain_error_2", "gain_error_2", &BalancingModel::gain_error_2, false, true},
    {"rotor_residual_1", "rotor_residual_1", &BalancingModel::rotor_residual_1, true, true},
    {"rotor_residual_2", "rotor_residual_2", &BalancingModel::rotor_residual_2, true, true},
    {"speed", "speed", &BalancingModel::speed, false, false},
    {"test_mass", "test_mass", &BalancingModel::test_mass, false, false},
    {"hole_radius", "hole_radius", &BalancingModel::hole_radius, false, false},
    {"hole_angle", "hole_angle", &BalancingModel::hole_angle, false, false},
    {"correction_mass", "correction_mass", &BalancingModel::correction_mass, false, false},
    {"correction_angle", "correction_angle", &BalancingModel::correction_angle, false, false},
};

inline std::string display_suffix(const engine::ToleranceSpec& s) {
  if (s.display_unit.empty()) return "";
  std::string u = s.display_unit;
  for (auto& ch : u) {
    if (ch == '*') ch = '_';
  }
  return "_" + u;
}

}  // namespace poise::kinds::balancing_machine::detail
