#include "cli/fit_command.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "cli/column_options.h"
#include "core/error.h"
#include "core/format.h"
#include "estimators/sine_fit.h"
#include "estimators/torque_table.h"

namespace poise::cli {
namespace {

const char* kFitHelp = R"(What it does:
  Fits the static unbalance torque measured with the turntable locked at angles theta_i
  (Yang, Zhao, Li, Wu 2015, Sec. 5.2, Eq. 22):

      M(theta) = MT_s sin(theta + b) + MK

  MT_s is the unbalance torque, b its phase, MK a constant disturbance torque. The model is
  linear in a = MT_s cos b, c = MT_s sin b and MK, so it is solved by linear least squares
  (QR); standard errors come from the residual spread (n - 3 degrees of freedom). The
  counterweight of Eq. 23 follows from the fit: m = MT_s / (R g), opposite the unbalance.

Data file (CSV, header on the first line, comma-separated):
  theta_deg,torque_mNm
  0.00,11.94
  10.00,13.26
  ...
  theta_deg is the turntable angle in degrees; exactly one torque column, its unit in its
  name: torque_mNm (mN*m) or torque_Nm (N*m). Optional time_s and sweep (+1/-1) columns;
  other columns are ignored. At least 4 rows and 3 distinct angles. Results are given in
  the file's torque unit.

Example (a worked example's measured table, 36 positions, from the project folder; how it
compares with its paper is in data/yang2015/README.md and studies/yang2015_loading_tests.toml):
  poise fit data/yang2015/table1_loading_test_36pt.csv
  poise fit data/yang2015/table1_loading_test_36pt.csv --json

Output: the fitted M(theta) with standard errors, rmse (RMS of residuals), sigma (residual
standard deviation), max |residual|, then theta, measured, fitted and residual per row.
--json prints one JSON object instead (amplitude, phase_deg, offset, standard_errors, rmse,
sigma, max_abs_residual, unit, n_points, residuals).
Exit status: 0 success, 2 invalid input (the message names the file, line and column).
)";

double rad_to_deg(double rad) { return rad * (180.0 / std::numbers::pi); }

// Decimals that show a value of the data's magnitude with 4 significant digits (12.47 mN*m,
// 0.01247 N*m), so the printout reads the same in either unit.
int decimals_for(const std::vector<double>& values) {
  double scale = 0.0;
  for (double v : values) scale = std::max(scale, std::abs(v));
  if (!(scale > 0.0)) return 3;
  return std::clamp(3 - static_cast<int>(std::floor(std::log10(scale))), 0, 12);
}

nlohmann::json to_json(const estimators::TorqueTable& t, const estimators::SineFitResult& f) {
  nlohmann::json residuals = nlohmann::json::array();
  for (std::size_t i = 0; i < t.size(); ++i) {
    residuals.push_back({{"theta_deg", t.theta_deg[i]},
                         {"measured", t.torque[i]},
                         {"fitted", estimators::sine_fit_predict(f, t.theta_rad[i])},
                         {"residual", f.residuals[i]}});
  }
  return {{"amplitude", f.amplitude},
          {"phase_deg", rad_to_deg(f.phase)},
          {"offset", f.offset},
          {"standard_errors",
           {{"amplitude", f.se_amplitude}, {"phase_deg", rad_to_deg(f.se_phase)}, {"offset", f.se_offset}}},
          {"rmse", f.rmse},
          {"sigma", f.sigma},
          {"max_abs_residual", f.max_abs_residual},
          {"unit", t.unit},
          {"n_points", f.n},
          {"residuals", std::move(residuals)}};
}

void print_text(const estimators::TorqueTable& t, const estimators::SineFitResult& f, std::ostream& out) {
  const int d = decimals_for(t.torque);
  const std::string& u = t.unit;
  const auto worst =
      static_cast<std::size_t>(std::max_element(f.residuals.begin(), f.residuals.end(),
                                                [](double x, double y) { return std::abs(x) < std::abs(y); }) -
                               f.residuals.begin());
  out << "Least-squares sine fit (Yang et al. 2015, Eq. 22) of " << f.n << " points from " << t.file << ", column "
      << t.torque_column << ":\n\n"
      << "  M(theta) = " << fixed(f.amplitude, d) << " sin(theta + " << fixed(rad_to_deg(f.phase), 2) << " deg) "
      << (f.offset < 0 ? "- " : "+ ") << fixed(std::abs(f.offset), d) << " " << u << "\n\n"
      << "  amplitude MT_s = " << fixed(f.amplitude, d + 1) << " +- " << fixed(f.se_amplitude, d + 1) << " " << u
      << "\n"
      << "  phase b        = " << fixed(rad_to_deg(f.phase), 3) << " +- " << fixed(rad_to_deg(f.se_phase), 3)
      << " deg\n"
      << "  offset MK      = " << fixed(f.offset, d + 1) << " +- " << fixed(f.se_offset, d + 1) << " " << u << "\n"
      << "  (+- one standard error, from the residual spread with n - 3 = " << f.n - 3 << " degrees of freedom)\n\n"
      << "  rmse           = " << fixed(f.rmse, d + 1) << " " << u << "  (RMS of residuals)\n"
      << "  sigma          = " << fixed(f.sigma, d + 1) << " " << u << "  (residual standard deviation)\n"
      << "  max |residual| = " << fixed(f.max_abs_residual, d + 1) << " " << u
      << "  (theta = " << fixed(t.theta_deg[worst], 2) << " deg, line " << t.rows[worst] << ")\n\n";
  const int w = 12;
  out << "  torque in " << u << ", residual = measured - fitted\n";
  out << fmt::format("  {:>{}} {:>{}} {:>{}} {:>{}}\n", "theta [deg]", w, "measured", w, "fitted", w, "residual", w);
  for (std::size_t i = 0; i < t.size(); ++i) {
    out << fmt::format("  {:>{}.2f} {:>{}.{}f} {:>{}.{}f} {:>{}.{}f}\n", t.theta_deg[i], w, t.torque[i], w, d + 1,
                       estimators::sine_fit_predict(f, t.theta_rad[i]), w, d + 1, f.residuals[i], w, d + 1);
  }
}

int run_fit(const std::string& path, bool json, const ColumnOptions& columns) {
  try {
    if (json) {
      std::cout << fit_torque_table(path, columns).dump(2) << '\n';
      return 0;
    }
    const estimators::TorqueTable table =
        estimators::read_torque_table(path, column_mapping(columns, estimators::torque_table_roles()));
    // Fit in the file's unit so the output repeats the measured values exactly as written.
    const estimators::SineFitResult fit = estimators::fit_sine(table.theta_rad, table.torque);
    { print_text(table, fit, std::cout); }
  } catch (const Error& e) {
    // Everything read_torque_table and fit_sine refuse is a problem with the input file.
    std::cerr << "poise: " << e.what() << "\nNothing was fitted.\n";
    return 2;
  }
  return 0;
}

}  // namespace

nlohmann::json fit_torque_table(const std::string& path, const ColumnOptions& columns) {
  const estimators::TorqueTable table =
      estimators::read_torque_table(path, column_mapping(columns, estimators::torque_table_roles()));
  // Fit in the file's unit so the output repeats the measured values exactly as written.
  return to_json(table, estimators::fit_sine(table.theta_rad, table.torque));
}

FitHandler add_fit_command(CLI::App& app) {
  struct Options {
    std::string data;
    bool json = false;
    ColumnOptions columns;
  };
  auto opt = std::make_shared<Options>();  // outlives this call: CLI11 writes into it
  CLI::App* sub =
      app.add_subcommand("fit", "least-squares sine fit of measured unbalance torque against turntable angle");
  sub->add_option("DATA", opt->data, "CSV file with columns theta_deg and torque_mNm (or torque_Nm)")->required();
  sub->add_flag("--json", opt->json, "print the fit as one JSON object");
  add_column_options(sub, opt->columns, estimators::torque_table_roles());
  sub->footer(kFitHelp);
  return [sub, opt]() -> std::optional<int> {
    if (!*sub) return std::nullopt;
    return run_fit(opt->data, opt->json, opt->columns);
  };
}

}  // namespace poise::cli
