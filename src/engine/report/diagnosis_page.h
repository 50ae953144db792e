#pragma once
/// report.html of `poise diagnose --out DIR`, made from diagnosis.json alone: the answer
/// first, then the data and the method, the effects found, the structure left, what the plan
/// cannot tell apart, the estimate before and after, the closed loop and the figure (plot.svg
/// inline: the page is one self-contained file).
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace poise::engine {

/// The page. `plot_svg`: the figure's file (its drawing set inline); `plot_note`: why there is
/// no figure ("" when there is one).
std::string diagnosis_report_html(const nlohmann::json& diagnosis, const std::filesystem::path& plot_svg,
                                  const std::string& plot_note);

}  // namespace poise::engine
