#include "cli/record_command.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "cli/column_options.h"
#include "cli/record_map_output.h"
#include "cli/record_report.h"
#include "cli/record_swing_output.h"
#include "core/error.h"
#include "core/format.h"
#include "core/units.h"
#include "engine/results/checked_file.h"
#include "engine/results/result_io.h"
#include "engine/study_files/toml_reader.h"
#include "estimators/oscillation_diagnosis.h"
#include "estimators/oscillation_record.h"
#include "estimators/record_map_diagnosis.h"
#include "estimators/record_motion.h"
#include "model_files/gimbal_model.h"

using namespace poise::model_files;  // the kinds' and model files' own namespaces

namespace poise::cli {
namespace {

struct Args {
  std::string model, out, file, kt_text = "0.05 N*m/A", theta_text = "30 deg";
  std::string report_dir;  ///< diagnose-record --out: record.json, figures, report.html
  std::vector<std::string> sets;
  std::uint64_t seed = 1;
  bool json = false;
  ColumnOptions columns;
};

int simulate(const Args& a) {
  std::map<std::string, std::string> overrides;
  for (const auto& s : a.sets) {
    const auto eq = s.find('=');
    if (eq == std::string::npos) throw Error("--set " + s + ": expected key=value, e.g. rotor.cogging_order=180");
    overrides[s.substr(0, eq)] = s.substr(eq + 1);
  }
  const model_files::GimbalModel m = model_files::load_gimbal_model(a.model, overrides);
  procedures::TestPlan plan = m.plan;
  double theta = 0.0;
  try {
    theta = units::parse_as(a.theta_text, units::kAngle);
  } catch (const Error& e) {
    throw Error("--theta '" + a.theta_text + "': " + e.what());
  }
  if (!(std::abs(theta) <= 10 * 2 * units::kPi)) {
    throw Error("--theta '" + a.theta_text + "': expected a turntable angle within +-3600 deg, e.g. \"30 deg\"");
  }
  plan.positions = {theta, theta + 0.5, theta + 1.0, theta + 1.5};  // the test needs 4; the first is recorded
  procedures::GimbalTruth truth;
  truth.disk = m.rotor;
  truth.disk.eccentricity = 25.81e-3 * 0.051 / m.rotor.mass;  // the paper's reference load, 12.91 mN*m
  truth.disk.eccentricity_angle = 45.5 * units::kRadPerDeg;
  truth.kt_true = m.plan.servo.kt_nominal;
  truth.disturbances = m.disturbances;
  procedures::StaticUnbalanceWorkspace ws(plan.solver);
  sampling::RandomStream rs(a.seed, sampling::StreamId::kProcedure, 0);
  std::vector<procedures::RecordSample> rec;
  procedures::MeasurementResult res;
  try {
    res = procedures::run_static_unbalance_procedure(plan, truth, rs, ws, 0, &rec);
  } catch (const Error& e) {
    // The solver's words name no key: say which values went in, the --set ones first.
    std::string set;
    for (const auto& [key, value] : overrides) set += (set.empty() ? "" : ", ") + key + " = " + value;
    throw Error(a.model + ": the simulation of the position theta = " + a.theta_text + " failed (" + e.what() +
                "): check the model's values" + (set.empty() ? std::string() : ", above all those set here: " + set));
  }
  std::string out = "time_s,current_A,phi_deg\n";
  for (const auto& s : rec) {
    fmt::format_to(std::back_inserter(out), "{:.6f},{:.9g},{:.9g}\n", s.t, s.current, s.phi / units::kRadPerDeg);
  }
  engine::write_file_atomic(a.out, out);  // WriteError: the file and the system's reason
  const double true_torque = m.rotor.mass * m.plan.gravity * truth.disk.eccentricity *
                             std::sin(res.positions[0].theta_true + truth.disk.eccentricity_angle);
  const double cable = m.rotor.torsion_stiffness * (m.plan.oscillation.centre - m.rotor.torsion_zero);
  std::printf(
      "wrote %zu samples of the position theta = %s to %s\n  Eq. 21 torque %.4f mN*m; unbalance torque "
      "m g e sin(theta + eps) = %.4f mN*m; K_T = %s\n  (Eq. 21 also carries the position's constant "
      "torques: cable k_CR (phi_c - phi_0) = %.4f mN*m and the current-sensor offset, %s + window noise "
      "%s rms)\n",
      rec.size(), a.theta_text.c_str(), a.out.c_str(), res.positions[0].torque * 1e3, true_torque * 1e3,
      units::format(m.plan.servo.kt_nominal, "N*m/A").c_str(), cable * 1e3,
      units::format(m.plan.acquisition.offset, "mA").c_str(),
      units::format(m.plan.acquisition.offset_noise, "mA").c_str());
  return 0;
}

// The diagnosis as --json prints it, or its text with the answer last; --out DIR: the folder.
int report(const Args& a, const nlohmann::json& j, const std::string& text, const RecordResiduals& residuals) {
  if (!a.report_dir.empty()) write_record_folder(a.report_dir, j, residuals);
  if (a.json) {
    std::cout << j.dump(2) << '\n';
    return 0;
  }
  std::cout << text << '\n' << j["answer"].get<std::string>() << '\n';
  if (!a.report_dir.empty()) {
    std::cout << "\nreport: " << (std::filesystem::path(a.report_dir) / "report.html").string() << '\n';
  }
  return 0;
}

int diagnose(const Args& a) {
  const RecordDiagnosis r = diagnose_record(a.file, a.kt_text, a.columns);
  return report(a, r.json, r.text, {r.angle, r.residual_before, r.residual_after});
}

}  // namespace

RecordDiagnosis diagnose_record(const std::string& file, const std::string& kt_text, const ColumnOptions& columns) {
  estimators::OscillationOptions opt;
  try {
    opt.kt = units::parse_as(kt_text, units::Dimension{{2, 1, -2, -1, 0, 0}});
  } catch (const Error& e) {
    throw Error("--kt '" + kt_text + "': " + e.what());
  }
  const estimators::OscillationRecord record =
      estimators::read_oscillation_record(file, column_mapping(columns, estimators::record_column_roles()));
  const std::string torque_source = record.torque.empty() ? "K_T = " + kt_text : "the torque as recorded";
  RecordDiagnosis r;
  try {
    const estimators::RecordMotion motion = estimators::record_motion(record, opt);
    if (motion.kind != "swing") {
      const estimators::MapDiagnosis map = estimators::diagnose_map(record, opt);
      r.json = map_diagnosis_json(map);
      r.json["reading"] = record.notes;
      r.text = map_diagnosis_text(map, record, torque_source);
      r.angle = map.angle;
      r.residual_before = map.residual_base;
      r.residual_after = map.residual_after;
    } else {
      const estimators::OscillationDiagnosis d = estimators::diagnose_oscillation(record, opt);
      r.json = swing_diagnosis_json(d, motion, record);
      r.text = swing_diagnosis_text(d, motion, record, torque_source);
      r.angle = d.angle;
      r.residual_before = d.residual_base;
      r.residual_after = d.residual_after;
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {  // e.g. a Boost.Math domain error from degenerate data
    throw Error(file + ": the record cannot be diagnosed (" + e.what() + "); check --kt (" + kt_text +
                ") and the record's columns and units");
  }
  r.json["file"] = file;
  r.json["answer"] = record_answer(r.json);
  return r;
}

std::function<std::optional<int>()> add_record_commands(CLI::App& app) {
  auto a = std::make_shared<Args>();
  CLI::App* sim =
      app.add_subcommand("simulate-record",
                         "simulate one turntable position of the static-unbalance test and write its raw record "
                         "(time_s, current_A, phi_deg); --set switches on effects the test's model lacks, e.g. "
                         "--set rotor.cogging_torque=\"0.3 mN*m\" --set rotor.cogging_order=180");
  sim->add_option("MODEL", a->model, "gimbal model file, e.g. models/gimbal_simulator_yang2015.toml")
      ->required()
      ->check(CLI::ExistingFile);
  sim->add_option("--out,-o", a->out, "record file to write (CSV)")->required();
  sim->add_option("--theta", a->theta_text, "turntable angle with its unit (default \"30 deg\")");
  sim->add_option("--set", a->sets, "model key=value override (repeatable)");
  sim->add_option("--seed", a->seed, "noise seed (default 1)");
  CLI::App* diag = app.add_subcommand(
      "diagnose-record",
      "residual diagnosis of a raw record (time, drive current or torque, angle) read as the lab wrote it. "
      "The motion is recognised first and only what it can show is fitted. A swing about a turntable "
      "position: K_T i = J phi'' + B phi' + C sign(phi') + K phi (+ gravity's curvature where it can show) + "
      "M_0, then cogging (orders from 360/swing, at least 20, to the record's Nyquist limit, confirmed away "
      "from the reversals), offset drift and friction asymmetry, and the position's torque before and after. "
      "A quasi-static map or laps: the torque against angle, Coulomb friction per direction where the record "
      "goes both ways, and a cogging map of every significant order from 1 per turn. Effects are added "
      "when significant (F test against the residual's local noise level, Holm or Bonferroni, BIC)");
  diag->add_option("RECORD", a->file,
                   "the record: a text table with columns of time, drive current (or torque) and angle; by "
                   "default time_s, current_A, phi_deg (what simulate-record writes)")
      ->required()
      ->check(CLI::ExistingFile);
  add_column_options(diag, a->columns, estimators::record_column_roles());
  diag->footer(R"(
A lab's file as it comes: comma, semicolon, tab or space delimited, comment lines (#, %, //),
headers with spaces, quoted cells, a NumPy .npy array (columns named 0, 1, ...), the time
stamps as logged, as numbers or as dates and times (jitter used as it is, gaps reported; a
stamp that repeats or goes back is an error), an angle that wraps once a turn. Name the columns and
units the file uses, e.g. a logger's "t [ms]; Iq; pos" with encoder counts of 16384 a turn
(one command, on one line):

  poise diagnose-record log.csv --column time="t [ms]" --column current=Iq --unit current=A
      --column angle=pos --unit angle="1/16384 rev" --kt "0.05 N*m/A"

A file that records the torque itself: --column torque=HEADER (K_T is then not used).)");
  diag->add_option("--kt", a->kt_text, "torque constant with its unit (default \"0.05 N*m/A\")");
  diag->add_flag("--json", a->json, "print one JSON object");
  diag->add_option("--out", a->report_dir,
                   "folder to write: record.json (the --json object), the figures (the cogging map, the residual "
                   "against angle before and after; gnuplot) and report.html, which opens with the answer");
  return [a, sim, diag]() -> std::optional<int> {
    try {
      if (*sim) return simulate(*a);
      if (*diag) return diagnose(*a);
    } catch (const engine::WriteError& e) {  // a full disk: a failed run, not bad input
      std::cerr << "poise: error: " << e.what() << '\n';
      return 1;
    } catch (const engine::ValidationError& e) {
      std::cerr << "poise: " << e.what() << '\n';
      return 2;
    } catch (const Error& e) {
      std::cerr << "poise: " << e.what() << '\n';
      return 2;
    } catch (const std::exception& e) {
      std::cerr << "poise: " << e.what() << '\n';
      return 2;
    }
    return std::nullopt;
  };
}

}  // namespace poise::cli
