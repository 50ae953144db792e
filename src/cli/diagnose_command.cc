// `poise diagnose`: the command line (options and --help text), reading and checking the
// input (data table, --load-*, --noise, --study) and the run that prints the result and
// writes --out DIR. The result's text and JSON: diagnose_text.cc; its files:
// diagnose_plot.cc and engine/report/diagnosis_page.cc.
#include "cli/diagnose_command.h"

#include "cli/diagnose_loop.h"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "cli/diagnose_output.h"
#include "core/error.h"
#include "core/units.h"
#include "engine/report/diagnosis_page.h"
#include "engine/results/result_io.h"
#include "estimators/residual_diagnosis.h"
#include "estimators/torque_table.h"

namespace poise::cli {
namespace {
namespace fs = std::filesystem;
namespace est = poise::estimators;
using nlohmann::json;

using diagnose_detail::Load;
using diagnose_detail::print_text;
using diagnose_detail::to_json;
using diagnose_detail::write_plot;

const char* kDiagnoseHelp = R"(What it does:
  Looks in a measured static unbalance table for effects that the Eq. 22 model
  M(theta) = MT_s sin(theta + b) + MK (Yang et al. 2015) lacks, and shows what they do to
  the unbalance estimate. Candidates: harmonics 2..K of the turntable angle, a time drift
  (linear, then quadratic), a direction offset between sweep directions, a step (scanned
  over change points), a saturating exponential drift (scanned over time constants), a drift
  of the torque constant scaling the whole M(theta), one outlier at a time, AR(1) errors in
  measurement order. Forward stepwise: each round tests every candidate (F test of the nested
  linear model; Bonferroni over a scanned family; for AR(1) the restricted likelihood ratio
  of Prais-Winsten GLS, one-sided: rho > 0), adjusts the round's p-values with Holm, and
  adds the best one only if its adjusted p < alpha AND it lowers the BIC. On data with none of these
  effects it adds one in at most about alpha of the cases.
  Then: what this plan cannot tell apart (candidates collinear with each other or with the
  first harmonic are reported together, with the estimate under each reading and a plan that
  would separate them); how far each effect moves the estimate in standard errors; an
  omnibus check of the final residual (lack of fit against repeated positions, the points'
  own standard errors (column torque_se_mNm) or --noise,
  Ljung-Box and runs tests in measurement order, CUSUM step scan, the largest periodogram
  ordinate in measurement order, for a period in time) that reports "unexplained
  structure" and where it sits. The estimate reported ("after") takes an ambiguous effect as
  the mean of its readings with their spread in its uncertainty, and ignores an outlier found
  in correlated noise; "selected model" is the estimate with every effect found.
  An effect that moves the estimate beyond 2 SE must earn it: when a competing explanation
  the data do not separate (another candidate within 10 BIC that an encompassing F test does
  not reject, AR(1) errors that its own test with AR(1) errors allowed cannot rule out on a
  one-direction sweep, or no effect) leaves the estimate where the plain fit has it, the
  estimate keeps the plain value, its uncertainty widened to span the readings, and the
  finding names the measurement that would separate them (reverse, repeat or shuffle the
  sweep; a second known load).
  Effects are reported by family (effects[].family): time_drift (a smooth drift in time, with
  effects[].shape "linear" or "exponential", or "not identifiable" where another time shape
  fits within 2 BIC, a direction offset or K_T drift within 6, or the estimate could not take
  it: "time effect; shape not identifiable", the competitor in effects[].alternative), step,
  kt_drift (K_T drifting: a multiplicative error), harmonic, direction_offset, outlier,
  autocorrelation. effects[].name stays the candidate fitted (time_drift,
  time_drift_quadratic, exponential_drift, step, kt_drift, ...).

Data file: as for `poise fit` (theta_deg and torque_mNm or torque_Nm). Optional columns:
  time_s (time of each point, s; without it, time = row order) and sweep (+1/-1, turntable
  direction; a direction offset needs both directions), torque_se_mNm or torque_se_Nm
  (standard error of each position's torque from the scatter of its period integrals).

Example (Table 1 of the paper, 25.81 g at 45.50 deg on r = 5.10 cm: 12.91 mN*m):
  poise diagnose data/yang2015/table1_loading_test_36pt.csv \
      --load-torque "12.91 mN*m" --load-angle "45.5 deg" --out /tmp/table1_diagnosis

Output: the base fit, each effect found with its parameters +- SE, p, Holm-adjusted p,
delta_BIC and physical causes, rmse and the unbalance estimate before and after, the errors
against the known load, and the candidates tested but not added. --json prints one object
(answer: the result in one sentence, also the text's last line; file, time_column,
sweep_column, max_harmonic, alpha, effects, rmse_before, rmse_after, estimate_before,
estimate_after, unit, n_points, estimate_selected_model, plan, omnibus, ambiguous,
collinearity, not_identifiable, notes, tested and, with a load, load, error_before, error_after; with --study, closed_loop).
--study STUDY.toml closes the loop: each effect found is mapped to its [disturbances] key of
the study's gimbal model (harmonic 2, time drift, direction offset, outlier), the study is
evaluated in memory without and with them (same random numbers, --study-samples each), and
the simulated errors are set beside the measured residual. --out DIR also writes diagnosis.json, plot.svg
(gnuplot; .gp and .dat kept) and report.html (self-contained; it opens with the answer).
Exit status: 0 success, 2 invalid input (the message names the file, line and column),
1 the output folder cannot be written.
)";

struct Options : DiagnoseRequest {
  std::string out;
  bool json = false;
};

std::optional<Load> parse_load(const DiagnoseRequest& o, const est::TorqueTable& t) {
  if (o.load_torque.empty() && o.load_angle.empty()) return std::nullopt;
  if (o.load_torque.empty() || o.load_angle.empty()) {
    throw Error(
        "--load-torque and --load-angle go together; expected both, e.g. "
        "--load-torque \"12.91 mN*m\" --load-angle \"45.5 deg\"");
  }
  Load l;
  try {
    l.torque = units::parse_as(o.load_torque, units::kTorque) / t.unit_factor;
  } catch (const Error& e) {
    throw Error("--load-torque '" + o.load_torque + "': " + e.what());
  }
  if (!(l.torque >= 0.0) || !(l.torque * t.unit_factor <= 1e9)) {  // the torque table's bound
    throw Error("--load-torque '" + o.load_torque +
                "': expected a torque >= 0 and at most 1e9 N*m, e.g. \"12.91 mN*m\"");
  }
  try {
    l.angle_rad = units::parse_as(o.load_angle, units::kAngle);
  } catch (const Error& e) {
    throw Error("--load-angle '" + o.load_angle + "': " + e.what());
  }
  if (!(std::abs(l.angle_rad) <= 10 * 2 * std::numbers::pi)) {
    throw Error("--load-angle '" + o.load_angle + "': expected an angle within +-3600 deg, e.g. \"45.5 deg\"");
  }
  return l;
}

// The table read and diagnosed, with its known load and the closed loop (--study).
struct Diagnosed {
  est::TorqueTable table;
  est::DiagnosisResult result;
  std::optional<Load> load;
  std::optional<LoopResult> loop;
  json j;
};

// Throws poise::Error (a ValidationError among them) for invalid input.
Diagnosed diagnose(const DiagnoseRequest& o) {
  Diagnosed d;
  d.table = est::read_torque_table(o.data, column_mapping(o.columns, est::torque_table_roles()));
  d.load = parse_load(o, d.table);
  est::DiagnosisOptions opt;
  opt.alpha = o.alpha;
  opt.max_harmonic = o.max_harmonic;
  if (!o.noise.empty()) {
    try {
      opt.noise = units::parse_as(o.noise, units::kTorque) / d.table.unit_factor;
    } catch (const Error& e) {
      throw Error("--noise '" + o.noise + "': " + e.what());
    }
    if (!(opt.noise > 0.0) || !std::isfinite(opt.noise)) {
      throw Error("--noise '" + o.noise + "': expected a torque > 0, e.g. \"0.2 mN*m\"");
    }
  }
  d.result = est::diagnose_residuals(d.table, opt);
  d.j = to_json(d.table, d.result, d.load, o.alpha);
  return d;
}

// The closed loop of --study on a diagnosis; throws poise::Error for an invalid study.
void close_loop(const DiagnoseRequest& o, Diagnosed& d) {
  if (o.study.empty()) return;
  if (o.study_samples < 2) throw Error("--study-samples " + std::to_string(o.study_samples) + ": expected >= 2");
  d.loop = close_the_loop(o.study, d.table, d.result, o.study_samples);
  d.j["closed_loop"] = loop_json(*d.loop);
}

int run_diagnose(const Options& o) {
  Diagnosed d;
  const fs::path dir(o.out);
  try {
    if (!o.out.empty() && fs::exists(dir / "diagnosis.json")) {
      throw Error(o.out +
                  " already holds diagnosis.json; expected a new or empty folder "
                  "(nothing is overwritten)");
    }
    d = diagnose(o);
  } catch (const Error& e) {
    std::cerr << "poise: " << e.what() << "\nNothing was diagnosed.\n";
    return 2;
  }
  try {
    close_loop(o, d);
  } catch (const Error& e) {  // ValidationError derives from Error
    std::cerr << "poise: " << e.what() << "\nNothing was printed: fix --study or leave it out.\n";
    return 2;
  }
  const est::TorqueTable& table = d.table;
  const est::DiagnosisResult& result = d.result;
  const std::optional<Load>& load = d.load;
  const std::optional<LoopResult>& loop = d.loop;
  const json& j = d.j;
  if (o.json) {
    std::cout << j.dump(2) << '\n';
  } else {
    print_text(table, result, o.alpha, load, std::cout);
    if (loop) std::cout << loop_text(*loop);
    std::cout << '\n' << j["answer"].get<std::string>() << '\n';
  }
  if (o.out.empty()) return 0;
  try {
    fs::create_directories(dir);
    engine::write_file_atomic((dir / "diagnosis.json").string(), j.dump(2) + "\n");
    const std::string note = write_plot(dir, table, result);
    engine::write_file_atomic((dir / "report.html").string(), engine::diagnosis_report_html(j, dir / "plot.svg", note));
    if (!o.json) std::cout << "\nreport: " << (dir / "report.html").string() << '\n';
    if (!note.empty()) std::cerr << "poise: " << note << '\n';
  } catch (const std::exception& e) {
    std::cerr << "poise: cannot write the output folder " << o.out << ": " << e.what() << '\n';
    return 1;
  }
  return 0;
}

}  // namespace

json diagnose_json(const DiagnoseRequest& request) {
  Diagnosed d = diagnose(request);
  close_loop(request, d);
  return d.j;
}

DiagnoseHandler add_diagnose_command(CLI::App& app) {
  auto opt = std::make_shared<Options>();  // outlives this call: CLI11 writes into it
  CLI::App* sub =
      app.add_subcommand("diagnose", "find effects beyond the Eq. 22 sine in measured unbalance torque data");
  sub->add_option("DATA", opt->data,
                  "CSV file with columns theta_deg and torque_mNm (or "
                  "torque_Nm), optional time_s and sweep")
      ->required();
  sub->add_flag("--json", opt->json, "print the diagnosis as one JSON object");
  add_column_options(sub, opt->columns, est::torque_table_roles());
  sub->add_option("--alpha", opt->alpha, "familywise level per round (Holm), default 0.05");
  sub->add_option("--max-harmonic", opt->max_harmonic,
                  "highest harmonic tried, default 6 (capped to keep 5 residual dof)");
  sub->add_option("--noise", opt->noise, "independent noise level of one point, e.g. \"0.2 mN*m\" (lack-of-fit test)");
  sub->add_option("--study", opt->study,
                  "a study whose kind's model takes measured effects (e.g. gimbal_static_unbalance, into its "
                  "[disturbances]): the effects found are added to its model and the simulated errors with and "
                  "without them are reported");
  sub->add_option("--study-samples", opt->study_samples, "samples of each --study evaluation, default 64");
  sub->add_option("--load-torque", opt->load_torque, "known load torque, e.g. \"12.91 mN*m\"");
  sub->add_option("--load-angle", opt->load_angle, "angle of the known load, e.g. \"45.5 deg\"");
  sub->add_option("--out", opt->out,
                  "folder for diagnosis.json, plot.svg and report.html (must not hold a "
                  "diagnosis.json)");
  sub->footer(kDiagnoseHelp);
  return [sub, opt]() -> std::optional<int> {
    if (!*sub) return std::nullopt;
    return run_diagnose(*opt);
  };
}

}  // namespace poise::cli
