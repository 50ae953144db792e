#pragma once
/// What `poise diagnose-record` says of a swing record (estimators/oscillation_diagnosis.h): its
/// JSON (the object --json prints) and its text. A map or laps: record_map_output.h.
#include <nlohmann/json.hpp>
#include <string>

#include "estimators/oscillation_diagnosis.h"
#include "estimators/record_motion.h"

namespace poise::cli {

nlohmann::json swing_diagnosis_json(const estimators::OscillationDiagnosis& d, const estimators::RecordMotion& motion,
                                    const estimators::OscillationRecord& record);

/// torque_source: "K_T = 0.05 N*m/A" or "the torque as recorded".
std::string swing_diagnosis_text(const estimators::OscillationDiagnosis& d, const estimators::RecordMotion& motion,
                                 const estimators::OscillationRecord& record, const std::string& torque_source);

}  // namespace poise::cli
