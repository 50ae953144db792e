#pragma once
/// report.html of `poise diagnose-record --out DIR`, assembled from the diagnosis' JSON (the
/// object `--json` prints, with its "answer"): the answer first, the motion and how the file was
/// read, the base model, the cogging map (a table, and a figure of amplitude against order), the
/// effects, what this motion cannot show and what lies outside physics, the residual before and
/// after against angle (figure), and the residual RMS after each effect.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace poise::engine {

/// figures: SVG files made beside the report (map.svg, residual.svg); note: why a figure is
/// missing ("" when none is).
std::string record_report_html(const nlohmann::json& diagnosis, const std::vector<std::filesystem::path>& figures,
                               const std::string& note);

}  // namespace poise::engine
