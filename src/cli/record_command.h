#pragma once
/// `poise simulate-record` and `poise diagnose-record`: the time-series level of the
/// residual diagnosis (one turntable position: time, drive current, gimbal angle).
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/column_options.h"

namespace poise::cli {

/// What `poise diagnose-record` finds in a record: the object --json prints (its "answer" in
/// one sentence), the text the command prints before the answer, and the residual against
/// angle before and after the effects found (the report's figure).
struct RecordDiagnosis {
  nlohmann::json json;
  std::string text;
  std::vector<double> angle, residual_before, residual_after;
};

/// Diagnoses the record `file` read with `columns` (roles and units), K_T given as text with
/// its unit ("0.05 N*m/A"). Throws poise::Error for a record it refuses or cannot diagnose.
RecordDiagnosis diagnose_record(const std::string& file, const std::string& kt_text, const ColumnOptions& columns);

/// Registers both subcommands; the returned handler runs whichever was given and returns
/// its exit status, or nothing if neither was.
std::function<std::optional<int>()> add_record_commands(CLI::App& app);

}  // namespace poise::cli
