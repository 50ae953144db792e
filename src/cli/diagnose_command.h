#pragma once
/// `poise diagnose DATA.csv [--json] [--alpha A] [--max-harmonic K]
///  [--load-torque "12.91 mN*m" --load-angle "45.5 deg"] [--out DIR]`: which effects beyond
/// the Eq. 22 sine (Yang et al. 2015) a measured static unbalance table holds (harmonics, time
/// drift, direction offset, outliers, AR(1) errors), what they do to the unbalance estimate
/// and, with a known load, to its error. Method: estimators/residual_diagnosis.h; input:
/// estimators/torque_table.h; see `poise diagnose --help`.
///
/// --out DIR (created; refused if it already holds diagnosis.json) receives diagnosis.json
/// (the --json object), plot.dat, plot.gp and plot.svg (gnuplot, SVG terminal; a missing
/// gnuplot is noted in the report, not an error) and report.html.
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/column_options.h"

namespace poise::cli {

/// What `poise diagnose` is given besides --json and --out (the options of the same names).
struct DiagnoseRequest {
  std::string data;
  double alpha = 0.05;
  int max_harmonic = 6;
  std::string noise;                    ///< "0.2 mN*m"; "" = none
  std::string load_torque, load_angle;  ///< a known load; both or neither
  std::string study;                    ///< a gimbal study to close the loop on; "" = none
  std::size_t study_samples = 64;
  ColumnOptions columns;  ///< --column, --unit: the file's own columns and units
};

/// The diagnosis as `poise diagnose --json` prints it (with "closed_loop" for a study).
/// Throws poise::Error (engine::ValidationError for a bad file) for invalid input.
nlohmann::json diagnose_json(const DiagnoseRequest& request);

/// Runs `poise diagnose` if it was the subcommand given: returns its exit status (0 success,
/// 2 invalid input, with the message on stderr, 1 when the output folder cannot be written),
/// or nullopt when another subcommand was given.
using DiagnoseHandler = std::function<std::optional<int>()>;

/// Registers the `diagnose` subcommand on app (before app is parsed). Call the returned
/// handler once app has parsed the command line.
DiagnoseHandler add_diagnose_command(CLI::App& app);

}  // namespace poise::cli
