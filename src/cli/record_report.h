#pragma once
/// What `poise diagnose-record` answers in one sentence (the terminal's last line, "answer" of
/// the JSON, the report's opening) and the files of `--out DIR`: record.json, the figures' data
/// and gnuplot scripts (map.*, residual.*) and report.html (engine/report/record_page.h).
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace poise::cli {

/// The residuals to draw: angle (rad), before and after (N m), in record order.
struct RecordResiduals {
  const std::vector<double>& angle;
  const std::vector<double>& before;
  const std::vector<double>& after;
};

/// The one sentence of a diagnosis JSON (map or swing).
std::string record_answer(const nlohmann::json& diagnosis);

/// Writes the folder (created; refused if it already holds record.json). Throws
/// engine::WriteError for a write the system refuses.
void write_record_folder(const std::filesystem::path& dir, const nlohmann::json& diagnosis, const RecordResiduals& r);

}  // namespace poise::cli
