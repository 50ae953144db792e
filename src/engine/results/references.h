#pragma once
/// Reference figures a study or model file declares, and their comparison with a run.
///
///   [[reference]]
///   name = "C_A loading tests: RMSE of MT_s"   # what the figure is
///   output = "C_A_rmse_torque_mNm"             # the study output it is set beside
///   statistic = "sample"                       # "sample" (default): one realisation (a
///                                              #   measured campaign), placed in the
///                                              #   simulated distribution; or mean, std,
///                                              #   p50, p95, p99_73, max: a figure of the
///                                              #   distribution, compared with its 95% CI
///   value = "0.78 mN*m"                        # with its unit (converted to the output's)
///   source = "Yang 2015, Table 2"
///   role = "validation"                        # or "calibration_target"
///   follows_from = "kt_drift, gimbal_zero"     # calibration target: what was tuned to it
///   tolerance = "5%"                           # optional (validation of a statistic): also
///                                              #   agrees when within this share
///
/// Only declared figures are compared: a study and model without [[reference]] get a report
/// with no reference content. A validation row gets a verdict; a calibration target is
/// shown as such (it follows from the calibration, so it agrees by construction) and is
/// never counted as agreement.
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/study_files/study_config.h"

namespace poise::engine {

class TomlReader;
struct OutputSpec;

/// Reads the [[reference]] tables of a file (errors recorded on the reader).
std::vector<ReferenceFigure> read_references(TomlReader& root);

/// Reads only the [[reference]] tables of a model file (the model's loader accepts them).
/// Throws ValidationError for a malformed reference.
std::vector<ReferenceFigure> read_model_references(const std::string& model_path);

/// The study's references and its model's, each checked against the study's outputs (an
/// output that exists, a value of its unit's dimension). Throws ValidationError.
std::vector<ReferenceFigure> declared_references(const StudyConfig& cfg, const std::vector<OutputSpec>& outputs);

/// The comparison for summary.json "references": one object per reference with the
/// simulated figure, its interval, where the reference falls and the verdict
/// ("agrees" | "disagrees" | "calibration_target", or "undecided" with "why" when fewer than
/// 40 samples ran for a one-realisation reference). `outputs_json` is summary.json's
/// "outputs" object; `values(name)` the ok samples of an output (nullptr if none).
nlohmann::json compare_references(const std::vector<ReferenceFigure>& refs, const std::vector<OutputSpec>& outputs,
                                  const nlohmann::json& outputs_json,
                                  const std::function<const std::vector<double>*(const std::string&)>& values);

}  // namespace poise::engine
