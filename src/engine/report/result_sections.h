#pragma once
/// The engine's HTML sections of a run's report, each made from summary.json's part of the
/// same name: the answer with its verdicts, declared references, Sobol indices, sample
/// convergence, contributions and sweeps. The report layer is where the engine assembles
/// HTML (the page itself: run_report.h; figures: report_plot.h, report_figures.h).
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/kind_interface/output_spec.h"

namespace poise::engine {

/// The report section for that comparison ("" when nothing is declared).
std::string references_html(const nlohmann::json& compared);

/// The report's opening: the answer in bold and a table of the verdicts.
std::string answer_html(const std::string& answer, const nlohmann::json& verdicts);

/// report.html section: per output, the tolerances that drive it, then the per-column detail.
std::string sensitivity_html(const nlohmann::json& sensitivity);

/// An HTML table of convergence_json for report.html.
std::string convergence_html(const nlohmann::json& convergence);

/// The report's section on them (a tornado per shown statistic written into plots_dir).
std::string contributions_html(const nlohmann::json& contributions, const nlohmann::json& requirements,
                               const std::vector<OutputSpec>& outputs, const std::filesystem::path& plots_dir,
                               bool plots);

/// The report's "Sweeps" section (figures written into plots_dir when `plots`).
std::string sweeps_html(const nlohmann::json& sweeps, const std::vector<OutputSpec>& outputs,
                        const std::filesystem::path& plots_dir, bool plots);

}  // namespace poise::engine
