#pragma once
/// report.html of `poise optimize`, made from its summary.json alone: the answer first (with
/// the fresh-sample verdict), then the fresh-sample check of the answer's design, the
/// optimum's own spread over seeds, the searches, the choices decided on fresh samples, the
/// Pareto front, the figures and the study's notes (marked as its author's text).
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace poise::engine {

/// The page. `figures`: SVG files in plots_dir set inline, in order.
std::string optimization_report_html(const nlohmann::json& summary, const std::filesystem::path& plots_dir,
                                     const std::vector<std::string>& figures);

}  // namespace poise::engine
