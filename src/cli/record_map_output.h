#pragma once
/// What `poise diagnose-record` says of a steps or laps record (estimators/record_map_diagnosis.h):
/// the motion first, then the torque per direction, the cogging map (every order with its
/// amplitude, phase, interval and resolution), what this motion cannot show, the residual
/// after each effect, and the lines that put the map into a gimbal model.
#include <nlohmann/json.hpp>
#include <string>

#include "estimators/oscillation_diagnosis.h"
#include "estimators/record_map_diagnosis.h"

namespace poise::cli {

nlohmann::json map_diagnosis_json(const estimators::MapDiagnosis& d);

/// The text of the diagnosis; torque_source: "K_T = 0.05 N*m/A" or "the torque as recorded".
std::string map_diagnosis_text(const estimators::MapDiagnosis& d, const estimators::OscillationRecord& record,
                               const std::string& torque_source);

}  // namespace poise::cli
