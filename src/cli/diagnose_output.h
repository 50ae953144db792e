#pragma once
/// Internal to `poise diagnose` (not a public API): what diagnose_command.cc,
/// diagnose_text.cc and diagnose_plot.cc share: the known load, the number and effect
/// formatting, and the result told as JSON, as text and as the files of --out DIR.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <ostream>
#include <string>

#include "estimators/residual_diagnosis.h"
#include "estimators/torque_table.h"

namespace poise::cli::diagnose_detail {

inline constexpr double kDegPerRad = 180.0 / std::numbers::pi;

struct Load {
  double torque = 0.0;  // in the table's unit
  double angle_rad = 0.0;
};

// diagnose_text.cc: formatting shared with the report (numbers: core/format.h).
std::string params_text(const estimators::Effect& e, const std::string& sep);
std::string effect_title(const estimators::Effect& e);
std::string estimate_text(const estimators::UnbalanceEstimate& e, const std::string& u);

// diagnose_text.cc: the --json object and the text report on the terminal.
nlohmann::json to_json(const estimators::TorqueTable& t, const estimators::DiagnosisResult& r,
                       const std::optional<Load>& load, double alpha);
/// The diagnosis in one sentence: the effects found, the unbalance estimate reported, what is
/// ambiguous and whether structure is left. The report opens with it; the terminal ends with it.
std::string answer_sentence(const estimators::TorqueTable& t, const estimators::DiagnosisResult& r);
void print_text(const estimators::TorqueTable& t, const estimators::DiagnosisResult& r, double alpha,
                const std::optional<Load>& load, std::ostream& out);

// diagnose_plot.cc: the figure of --out DIR (report.html: engine/report/diagnosis_page.h).
// plot.dat, plot.gp and (if gnuplot runs) plot.svg; returns the note for the report.
std::string write_plot(const std::filesystem::path& dir, const estimators::TorqueTable& t,
                       const estimators::DiagnosisResult& r);

}  // namespace poise::cli::diagnose_detail
