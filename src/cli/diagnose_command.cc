#include "cli/diagnose_command.h"

#include "cli/diagnose_loop.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <numeric>
#include <sstream>
#include <string>
#include <tuple>

#include "core/error.h"
#include "core/units.h"
#include "estimators/residual_diagnosis.h"
#include "estimators/torque_table.h"
#include "engine/report_plot.h"
#include "engine/result_io.h"

namespace poise::cli {
namespace {
namespace fs = std::filesystem;
namespace est = poise::estimators;
using nlohmann::json;

const char* kDiagnoseHelp = R"(What it does:
  Looks in a measured static unbalance table for effects that the Eq. 22 model
  M(theta) = MT_s sin(theta + b) + MK (Yang et al. 2015) lacks, and shows what they do to
  the unbalance estimate. Candidates: harmonics 2..K of the turntable angle, a time drift
  (linear, then quadratic), a direction offset between sweep directions, a step (scanned
  over change points), a saturating exponential drift (scanned over time constants), a drift
  of the torque constant scaling the whole M(theta), one outlier at a time, AR(1) errors in
  measurement order. Forward stepwise: each round tests every candidate (F test of the nested
  linear model; Bonferroni over a scanned family; restricted likelihood ratio of
  Prais-Winsten GLS for AR(1)), adjusts the round's p-values with Holm, and adds the best
  one only if its adjusted p < alpha AND it lowers the BIC. On data with none of these
  effects it adds one in at most about alpha of the cases.
  Then: what this plan cannot tell apart (candidates collinear with each other or with the
  first harmonic are reported together, with the estimate under each reading and a plan that
  would separate them); how far each effect moves the estimate in standard errors; an
  omnibus check of the final residual (lack of fit against repeated positions, the points'
  own standard errors (column torque_se_mNm) or --noise,
  Ljung-Box and runs tests in measurement order, CUSUM step scan) that reports "unexplained
  structure" and where it sits. The estimate reported ("after") takes an ambiguous effect as
  the mean of its readings with their spread in its uncertainty, and ignores an outlier found
  in correlated noise; "selected model" is the estimate with every effect found.

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
(effects, rmse_before, rmse_after, estimate_before, estimate_after, unit, n_points,
estimate_selected_model, plan, omnibus, ambiguous, collinearity, not_identifiable, notes
and, with a load, load, error_before, error_after; with --study, closed_loop).
--study STUDY.toml closes the loop: each effect found is mapped to its [disturbances] key of
the study's gimbal model (harmonic 2, time drift, direction offset, outlier), the study is
evaluated in memory without and with them (same random numbers, --study-samples each), and
the simulated errors are set beside the measured residual. --out DIR also writes diagnosis.json, plot.svg
(gnuplot; .gp and .dat kept) and report.html.
Exit status: 0 success, 2 invalid input (the message names the file, line and column),
1 the output folder cannot be written.
)";

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

struct Options {
  std::string data, out, load_torque, load_angle;
  bool json = false;
  double alpha = 0.05;
  int max_harmonic = 6;
  std::string noise;
  std::string study;
  std::size_t study_samples = 64;
};

struct Load {
  double torque = 0.0;  // in the table's unit
  double angle_rad = 0.0;
};

std::string num(double v, int significant = 4) {
  if (!std::isfinite(v)) return "n/a";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", significant, v);
  return buf;
}

// HTML text; a line break becomes <br>.
std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    const char* r = c == '<'    ? "&lt;"
                    : c == '>'  ? "&gt;"
                    : c == '&'  ? "&amp;"
                    : c == '"'  ? "&quot;"
                    : c == '\n' ? "<br>"
                                : nullptr;
    o += r ? std::string(r) : std::string(1, c);
  }
  return o;
}

json estimate_json(const est::UnbalanceEstimate& e) {
  return {{"amplitude", e.amplitude},
          {"phase_deg", e.phase * kDegPerRad},
          {"offset", e.offset},
          {"se_amplitude", e.se_amplitude},
          {"se_phase_deg", e.se_phase * kDegPerRad},
          {"se_offset", e.se_offset}};
}

json to_json(const est::TorqueTable& t, const est::DiagnosisResult& r,
             const std::optional<Load>& load) {
  json effects = json::array();
  for (const est::Effect& e : r.effects) {
    json params = json::object();
    for (const auto& p : e.params)
      params[p.name] = {{"value", p.value}, {"se", p.se}, {"unit", p.unit}};
    json j = {{"name", e.name},           {"params", params},
              {"p_value", e.p_value},     {"p_adjusted", e.p_adjusted},
              {"delta_bic", e.delta_bic}, {"causes", e.causes}};
    if (e.name == "harmonic") j["order"] = e.order;
    if (e.name == "outlier" || e.name == "step") j["index"] = e.index, j["line"] = e.line;
    j["shift_se"] = e.shift_se;
    j["r_first_harmonic"] = e.r_first_harmonic;
    j["moves_estimate"] = e.moves_estimate;
    if (!e.estimate_note.empty()) j["estimate_note"] = e.estimate_note;
    effects.push_back(std::move(j));
  }
  json omnibus = {{"p_value", r.omnibus.p_value},
                  {"unexplained_structure", r.omnibus.unexplained},
                  {"where", r.omnibus.where},
                  {"message", r.omnibus.message},
                  {"tests", json::array()}};
  for (const est::StructureTest& st : r.omnibus.tests) {
    json tj = {{"name", st.name}, {"examined", st.examined}, {"note", st.note}};
    if (st.examined) tj["statistic"] = st.statistic, tj["p_value"] = st.p_value;
    omnibus["tests"].push_back(std::move(tj));
  }
  json ambiguous = json::array();
  for (const est::AmbiguousFinding& a : r.ambiguous) {
    json readings = json::array();
    for (const est::Reading& rd : a.readings) {
      readings.push_back(
          {{"effects", rd.effects}, {"delta_bic", rd.delta_bic}, {"estimate", estimate_json(rd.estimate)}});
    }
    ambiguous.push_back(
        {{"readings", readings}, {"correlation", a.correlation}, {"why", a.why}, {"plan", a.plan}});
  }
  json collinearity = json::array();
  for (const est::CandidateCollinearity& c : r.collinearity) {
    collinearity.push_back({{"candidate", c.candidate},
                            {"r_first_harmonic", c.r_first_harmonic},
                            {"vif_base", std::isfinite(c.vif_base) ? json(c.vif_base) : json("inf")},
                            {"most_collinear_with", c.most_collinear_with},
                            {"r_other", c.r_other}});
  }
  json not_identifiable = json::array();
  for (const auto& [name, why] : r.not_identifiable) {
    not_identifiable.push_back({{"name", name}, {"why", why}});
  }
  json out = {{"effects", effects},
              {"rmse_before", r.rmse_before},
              {"rmse_after", r.rmse_after},
              {"estimate_before", estimate_json(r.estimate_before)},
              {"estimate_after", estimate_json(r.estimate_after)},
              {"unit", t.unit},
              {"n_points", t.size()},
              {"estimate_selected_model", estimate_json(r.estimate_selected)},
              {"plan", r.plan},
              {"omnibus", omnibus},
              {"ambiguous", ambiguous},
              {"collinearity", collinearity},
              {"not_identifiable", not_identifiable},
              {"notes", r.notes}};
  if (load) {
    const est::KnownLoadErrors k = est::known_load_errors(r, load->torque, load->angle_rad);
    out["load"] = {{"torque", load->torque}, {"angle_deg", load->angle_rad * kDegPerRad}};
    out["error_before"] = {{"amplitude", k.before.amplitude}, {"phase_deg", k.before.phase_deg}};
    out["error_after"] = {{"amplitude", k.after.amplitude}, {"phase_deg", k.after.phase_deg}};
  }
  return out;
}

std::string params_text(const est::Effect& e, const std::string& sep) {
  std::string s;
  for (const auto& p : e.params) {
    s += (s.empty() ? "" : sep) + p.name + " = " + num(p.value) + " +- " + num(p.se, 2) +
         (p.unit.empty() ? "" : " " + p.unit);
  }
  return s;
}

std::string effect_title(const est::Effect& e) {
  if (e.name == "harmonic") return "harmonic " + std::to_string(e.order);
  if (e.name == "outlier") {
    return "outlier at row " + std::to_string(e.index) + " (file line " + std::to_string(e.line) +
           ")";
  }
  if (e.name == "step") {
    return "step before row " + std::to_string(e.index) + " (file line " + std::to_string(e.line) +
           ")";
  }
  return e.name;
}

std::string estimate_text(const est::UnbalanceEstimate& e, const std::string& u) {
  return "amplitude " + num(e.amplitude, 5) + " +- " + num(e.se_amplitude, 2) + " " + u +
         ", phase " + num(e.phase * kDegPerRad, 5) + " +- " + num(e.se_phase * kDegPerRad, 2) +
         " deg, offset " + num(e.offset, 4) + " +- " + num(e.se_offset, 2) + " " + u;
}

std::string error_text(const est::EstimateError& e, const std::string& u) {
  return "amplitude " + num(e.amplitude, 3) + " " + u + ", phase " + num(e.phase_deg, 3) +
         " deg, unbalance left after correction " + num(e.vector, 3) + " " + u;
}

void print_text(const est::TorqueTable& t, const est::DiagnosisResult& r, double alpha,
                const std::optional<Load>& load, std::ostream& out) {
  const std::string& u = t.unit;
  const auto& b = r.estimate_before;
  out << "Residual diagnosis of " << t.size() << " points from " << t.file << " (torque in " << u
      << "; time: " << (t.time_s.empty() ? "row order" : "column time_s")
      << "; sweep: " << (t.sweep.empty() ? "none" : "column sweep") << ")\n"
      << "Searched: harmonics 2.." << r.max_harmonic
      << ", time drift, K_T drift, direction offset, step, exponential settling, outliers, AR(1) "
         "errors; forward stepwise, Holm per round at alpha = "
      << alpha << ", delta_BIC < 0\n\n"
      << "Base fit (Eq. 22): M(theta) = " << num(b.amplitude, 5) << " sin(theta + "
      << num(b.phase * kDegPerRad, 4) << " deg) + " << num(b.offset, 4) << " " << u << "\n\n";
  out << "Effects found (in the order added):" << (r.effects.empty() ? " none\n" : "\n");
  for (std::size_t i = 0; i < r.effects.size(); ++i) {
    const est::Effect& e = r.effects[i];
    out << "  " << i + 1 << ". " << effect_title(e) << ": " << params_text(e, ", ") << "\n"
        << "     p = " << num(e.p_value, 3) << ", Holm-adjusted p = " << num(e.p_adjusted, 3)
        << ", delta_BIC = " << num(e.delta_bic, 3) << "\n"
        << "     causes: " << e.causes << "\n"
        << "     moves the unbalance estimate by " << num(e.shift_se, 3)
        << " SE; trades off with the first harmonic at r = " << num(e.r_first_harmonic, 3)
        << (e.moves_estimate ? "" : "; " + e.estimate_note) << "\n";
  }
  for (const auto& s : r.notes) out << "  note: " << s << "\n";
  out << "\nPlan: " << r.plan << "\n"
      << "Collinearity under this plan (r1: canonical correlation with the first harmonic; VIF "
         "against Eq. 22; the closest other candidate, base projected out; limit 0.9):\n";
  for (const est::CandidateCollinearity& c : r.collinearity) {
    out << "  " << c.candidate << ": r1 " << num(c.r_first_harmonic, 3) << ", VIF "
        << num(c.vif_base, 3) << (c.most_collinear_with.empty() ? "" : ", closest " +
                                   c.most_collinear_with + " at r " + num(c.r_other, 3))
        << (c.r_other >= 0.9 || c.r_first_harmonic >= 0.9 || c.vif_base >= 1.0 / (1.0 - 0.81)
                ? "  (not separable on this plan)"
                : "")
        << "\n";
  }
  for (std::size_t i = 0; i < r.ambiguous.size(); ++i) {
    const est::AmbiguousFinding& a = r.ambiguous[i];
    out << "Ambiguous finding " << i + 1 << ": " << a.why << "\n";
    for (const est::Reading& rd : a.readings) {
      out << "  reading " << rd.effects << " (delta_BIC " << num(rd.delta_bic, 3)
          << "): " << estimate_text(rd.estimate, u) << "\n";
    }
    out << "  a plan that would separate them: " << a.plan << "\n";
  }
  out << "\nOmnibus check of the final residual: " << r.omnibus.message << "\n";
  for (const est::StructureTest& st : r.omnibus.tests) {
    out << "  " << st.name << ": "
        << (st.examined ? "statistic " + num(st.statistic, 4) + ", p = " + num(st.p_value, 3) +
                              (st.note.empty() ? "" : " (" + st.note + ")")
                        : st.note)
        << "\n";
  }
  for (const auto& [name, why] : r.not_identifiable) {
    out << "Not identifiable from one test: " << name << ": " << why << "\n";
  }
  out << "\nCandidates tested in the last round, not added:\n";
  for (const auto& s : r.tested) out << "  " << s << "\n";
  out << "\nrmse (sqrt(RSS/n)): before " << num(r.rmse_before) << " " << u << ", after "
      << num(r.rmse_after) << " " << u << "\n"
      << "Unbalance estimate (first harmonic, +- 1 SE):\n"
      << "  before: " << estimate_text(r.estimate_before, u) << "\n"
      << "  selected model: " << estimate_text(r.estimate_selected, u) << "\n"
      << "  after:  " << estimate_text(r.estimate_after, u)
      << " (the estimate reported: see the effects' notes)\n";
  if (load) {
    const est::KnownLoadErrors k = est::known_load_errors(r, load->torque, load->angle_rad);
    out << "Error against the known load " << num(load->torque) << " " << u << " at "
        << num(load->angle_rad * kDegPerRad) << " deg (estimate - load):\n"
        << "  before: " << error_text(k.before, u) << "\n"
        << "  after:  " << error_text(k.after, u) << "\n";
  }
}

// plot.dat, plot.gp and (if gnuplot runs) plot.svg; returns the note for the report.
std::string write_plot(const fs::path& dir, const est::TorqueTable& t,
                       const est::DiagnosisResult& r) {
  std::vector<std::size_t> idx(t.size());
  std::iota(idx.begin(), idx.end(), std::size_t{0});
  std::stable_sort(idx.begin(), idx.end(),
                   [&](auto a, auto b) { return t.theta_deg[a] < t.theta_deg[b]; });
  std::ostringstream dat;
  dat << "# theta_deg measured fitted_before fitted_after residual_before residual_after ("
      << t.unit << ")\n";
  dat.precision(10);
  for (std::size_t i : idx) {
    dat << t.theta_deg[i] << ' ' << t.torque[i] << ' ' << r.fitted_before[i] << ' '
        << r.fitted_after[i] << ' ' << r.residual_before[i] << ' ' << r.residual_after[i] << '\n';
  }
  studies::write_file_atomic((dir / "plot.dat").string(), dat.str());
  const auto& b = r.estimate_before;
  std::ostringstream gp;
  gp.precision(12);
  gp << "set terminal svg size 900,760 noenhanced font 'Helvetica,12' background rgb 'white'\n"
     << "set output 'plot.svg'\nset samples 721\nset grid\nset autoscale xfix\nset key below "
        "horizontal\n"
     << "set multiplot layout 2,1 title 'Residual diagnosis of "
     << fs::path(t.file).filename().string() << "'\n"
     << "set xlabel 'turntable angle theta [deg]'\nset ylabel 'torque [" << t.unit << "]'\n"
     << "A = " << b.amplitude << "; B = " << b.phase << "; K = " << b.offset << "\n"
     << "plot 'plot.dat' u 1:2 w p pt 7 ps 0.7 lc rgb '#000000' t 'measured', \\\n"
     << "  A*sin(x*pi/180 + B) + K w l lw 2 lc rgb '#1f77b4' t 'base fit (Eq. 22)', \\\n"
     << "  'plot.dat' u 1:4 w p pt 6 ps 1.0 lc rgb '#d62728' t 'final model'\n"
     << "set ylabel 'residual [" << t.unit << "]'\n"
     << "plot 'plot.dat' u 1:5 w lp pt 7 ps 0.6 lc rgb '#1f77b4' t 'base fit residual', \\\n"
     << "  'plot.dat' u 1:6 w lp pt 6 ps 0.8 lc rgb '#d62728' t 'final model residual', \\\n"
     << "  0 w l lc rgb '#808080' notitle\nunset multiplot\n";
  studies::write_file_atomic((dir / "plot.gp").string(), gp.str());
  std::string why;
  if (studies::run_gnuplot((dir / "plot.gp").string(), &why) && fs::exists(dir / "plot.svg")) {
    return "";
  }
  if (why.empty()) why = "gnuplot wrote no plot.svg";
  return why + " (run gnuplot plot.gp in this folder to retry).";
}

void write_report(const fs::path& dir, const est::TorqueTable& t, const est::DiagnosisResult& r,
                  const json& j, double alpha, const std::string& plot_note) {
  const std::string& u = t.unit;
  std::ostringstream h;
  h << "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>Residual diagnosis: "
    << esc(t.file) << "</title><style>body{font-family:sans-serif;max-width:1000px;margin:2em "
    << "auto}table{border-collapse:collapse}td,th{border:1px solid #aaa;padding:4px 8px;"
    << "vertical-align:top}th{background:#eee}</style></head><body>\n"
    << "<h1>Residual diagnosis of a static unbalance measurement</h1>\n<p>Data: <code>"
    << esc(t.file) << "</code>, " << t.size() << " points, torque in " << esc(u)
    << "; time: " << (t.time_s.empty() ? "row order" : "column time_s")
    << "; sweep: " << (t.sweep.empty() ? "none" : "column sweep")
    << ".</p>\n<p>Base model (Yang et al. 2015, "
    << "Eq. 22): M(theta) = MT_s sin(theta + b) + MK. Candidates: harmonics 2.." << r.max_harmonic
    << ", time drift, direction offset, outliers, AR(1) errors, added by "
    << "forward stepwise selection (F test or likelihood ratio, Holm-adjusted per round, "
    << "alpha = " << alpha << ", and delta_BIC &lt; 0).</p>\n<h2>Findings</h2>\n";
  if (r.effects.empty()) {
    h << "<p>No effect beyond Eq. 22 was found: the base model explains the data within its "
         "noise.</p>\n";
  } else {
    h << "<table><tr><th>#</th><th>effect</th><th>parameters (&plusmn; SE)</th><th>p</th>"
         "<th>Holm p</th><th>&Delta;BIC</th><th>possible causes</th></tr>\n";
    for (std::size_t i = 0; i < r.effects.size(); ++i) {
      const est::Effect& e = r.effects[i];
      h << "<tr><td>" << i + 1 << "</td><td>" << esc(effect_title(e)) << "</td><td>"
        << esc(params_text(e, "\n")) << "</td><td>" << num(e.p_value, 3) << "</td><td>"
        << num(e.p_adjusted, 3) << "</td><td>" << num(e.delta_bic, 3) << "</td><td>"
        << esc(e.causes) << "</td></tr>\n";
    }
    h << "</table>\n";
  }
  for (const auto& s : r.notes) h << "<p><i>Note: " << esc(s) << "</i></p>\n";
  h << "<h2>Unexplained structure</h2>\n<p>" << (r.omnibus.unexplained ? "<b>" : "")
    << esc(r.omnibus.message) << (r.omnibus.unexplained ? "</b>" : "") << "</p>\n<ul>\n";
  for (const est::StructureTest& st : r.omnibus.tests) {
    h << "<li>" << esc(st.name) << ": "
      << (st.examined ? "p = " + num(st.p_value, 3) + (st.note.empty() ? "" : " (" + esc(st.note) + ")")
                      : esc(st.note))
      << "</li>\n";
  }
  h << "</ul>\n<h2>What this plan cannot tell apart</h2>\n<p>Plan: " << esc(r.plan) << ".</p>\n"
    << "<table><tr><th>candidate</th><th>r with the first harmonic</th><th>VIF against Eq. 22"
    << "</th><th>closest other candidate</th><th>r</th></tr>\n";
  for (const est::CandidateCollinearity& c : r.collinearity) {
    h << "<tr><td>" << esc(c.candidate) << "</td><td>" << num(c.r_first_harmonic, 3) << "</td><td>"
      << num(c.vif_base, 3) << "</td><td>" << esc(c.most_collinear_with) << "</td><td>"
      << num(c.r_other, 3) << "</td></tr>\n";
  }
  h << "</table>\n";
  for (const est::AmbiguousFinding& a : r.ambiguous) {
    h << "<p>" << esc(a.why) << ".</p>\n<table><tr><th>reading</th><th>&Delta;BIC</th>"
      << "<th>unbalance estimate</th></tr>\n";
    for (const est::Reading& rd : a.readings) {
      h << "<tr><td>" << esc(rd.effects) << "</td><td>" << num(rd.delta_bic, 3) << "</td><td>"
        << esc(estimate_text(rd.estimate, u)) << "</td></tr>\n";
    }
    h << "</table>\n<p>A plan that would separate them: " << esc(a.plan) << ".</p>\n";
  }
  for (const auto& [name, why] : r.not_identifiable) {
    h << "<p>Not identifiable from one test: <b>" << esc(name) << "</b>: " << esc(why) << ".</p>\n";
  }
  const auto row = [&](const std::string& name, const json& a, const json& b2, const char* key,
                       const std::string& unit) {
    h << "<tr><td>" << name << "</td><td>" << num(a.at(key).get<double>(), 5) << "</td><td>"
      << num(b2.at(key).get<double>(), 5) << "</td><td>" << esc(unit) << "</td></tr>\n";
  };
  h << "<h2>Before and after</h2>\n<table><tr><th></th><th>base fit</th><th>final model</th>"
       "<th>unit</th></tr>\n";
  h << "<tr><td>rmse</td><td>" << num(r.rmse_before, 4) << "</td><td>" << num(r.rmse_after, 4)
    << "</td><td>" << esc(u) << "</td></tr>\n";
  for (const auto& [name, key, unit] :
       {std::tuple<std::string, const char*, std::string>{"amplitude MT_s", "amplitude", u},
        {"SE amplitude", "se_amplitude", u},
        {"phase b", "phase_deg", "deg"},
        {"SE phase", "se_phase_deg", "deg"},
        {"offset MK", "offset", u},
        {"SE offset", "se_offset", u}}) {
    row(name, j["estimate_before"], j["estimate_after"], key, unit);
  }
  if (j.contains("load")) {
    h << "<tr><th colspan=\"4\">against the known load " << num(j["load"]["torque"].get<double>())
      << " " << esc(u) << " at " << num(j["load"]["angle_deg"].get<double>()) << " deg "
      << "(estimate - load)</th></tr>\n";
    row("amplitude error", j["error_before"], j["error_after"], "amplitude", u);
    row("phase error", j["error_before"], j["error_after"], "phase_deg", "deg");
  }
  h << "</table>\n";
  if (j.contains("closed_loop")) {
    h << "<h2>The loop closed in the simulation model</h2>\n<p>"
      << esc(j["closed_loop"]["sentence"].get<std::string>()) << "</p>\n<ul>\n";
    for (const auto& [k, v] : j["closed_loop"]["overrides"].items()) {
      h << "<li><code>" << esc(k) << " = " << esc(v.get<std::string>()) << "</code></li>\n";
    }
    h << "</ul>\n";
  }
  h << "<h2>Plot</h2>\n";
  if (plot_note.empty()) {
    h << "<p><img src=\"plot.svg\" alt=\"data, base fit and final model against theta; "
         "residuals\" style=\"max-width:100%\"></p>\n";
  } else {
    h << "<p><b>" << esc(plot_note) << "</b></p>\n";
  }
  h << "<p>Upper panel: measured points, the base fit and the final model at each point. Lower"
       " panel: residuals of both (with AR(1) errors the final residual is the innovation; a "
       "flagged outlier's residual is 0).</p>\n<h2>Candidates tested in the last round, not "
       "added</h2>\n<ul>\n";
  for (const auto& s : r.tested) h << "<li>" << esc(s) << "</li>\n";
  h << "</ul>\n<p><small>Files: diagnosis.json, plot.dat, plot.gp, plot.svg, report.html."
       "</small></p>\n</body></html>\n";
  studies::write_file_atomic((dir / "report.html").string(), h.str());
}

std::optional<Load> parse_load(const Options& o, const est::TorqueTable& t) {
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

int run_diagnose(const Options& o) {
  est::TorqueTable table;
  est::DiagnosisResult result;
  std::optional<Load> load;
  const fs::path dir(o.out);
  try {
    if (!o.out.empty() && fs::exists(dir / "diagnosis.json")) {
      throw Error(o.out +
                  " already holds diagnosis.json; expected a new or empty folder "
                  "(nothing is overwritten)");
    }
    table = est::read_torque_table(o.data);
    load = parse_load(o, table);
    est::DiagnosisOptions opt;
    opt.alpha = o.alpha;
    opt.max_harmonic = o.max_harmonic;
    if (!o.noise.empty()) {
      try {
        opt.noise = units::parse_as(o.noise, units::kTorque) / table.unit_factor;
      } catch (const Error& e) {
        throw Error("--noise '" + o.noise + "': " + e.what());
      }
      if (!(opt.noise > 0.0) || !std::isfinite(opt.noise)) {
        throw Error("--noise '" + o.noise + "': expected a torque > 0, e.g. \"0.2 mN*m\"");
      }
    }
    result = est::diagnose_residuals(table, opt);
  } catch (const Error& e) {
    std::cerr << "poise: " << e.what() << "\nNothing was diagnosed.\n";
    return 2;
  }
  std::optional<LoopResult> loop;
  if (!o.study.empty()) {
    try {
      if (o.study_samples < 2) throw Error("--study-samples " + std::to_string(o.study_samples) + ": expected >= 2");
      loop = close_the_loop(o.study, table, result, o.study_samples);
    } catch (const Error& e) {  // ValidationError derives from Error
      std::cerr << "poise: " << e.what() << "\nNothing was printed: fix --study or leave it out.\n";
      return 2;
    }
  }
  json j = to_json(table, result, load);
  if (loop) j["closed_loop"] = loop_json(*loop);
  if (o.json) {
    std::cout << j.dump(2) << '\n';
  } else {
    print_text(table, result, o.alpha, load, std::cout);
    if (loop) std::cout << loop_text(*loop);
  }
  if (o.out.empty()) return 0;
  try {
    fs::create_directories(dir);
    studies::write_file_atomic((dir / "diagnosis.json").string(), j.dump(2) + "\n");
    const std::string note = write_plot(dir, table, result);
    write_report(dir, table, result, j, o.alpha, note);
    if (!o.json) std::cout << "\nreport: " << (dir / "report.html").string() << '\n';
    if (!note.empty()) std::cerr << "poise: " << note << '\n';
  } catch (const std::exception& e) {
    std::cerr << "poise: cannot write the output folder " << o.out << ": " << e.what() << '\n';
    return 1;
  }
  return 0;
}

}  // namespace

DiagnoseHandler add_diagnose_command(CLI::App& app) {
  auto opt = std::make_shared<Options>();  // outlives this call: CLI11 writes into it
  CLI::App* sub = app.add_subcommand(
      "diagnose", "find effects beyond the Eq. 22 sine in measured unbalance torque data");
  sub->add_option("DATA", opt->data,
                  "CSV file with columns theta_deg and torque_mNm (or "
                  "torque_Nm), optional time_s and sweep")
      ->required();
  sub->add_flag("--json", opt->json, "print the diagnosis as one JSON object");
  sub->add_option("--alpha", opt->alpha, "familywise level per round (Holm), default 0.05");
  sub->add_option("--max-harmonic", opt->max_harmonic,
                  "highest harmonic tried, default 6 (capped to keep 5 residual dof)");
  sub->add_option("--noise", opt->noise,
                  "independent noise level of one point, e.g. \"0.2 mN*m\" (lack-of-fit test)");
  sub->add_option("--study", opt->study,
                  "a gimbal_static_unbalance study: the effects found are added to its model's "
                  "[disturbances] and the simulated errors with and without them are reported");
  sub->add_option("--study-samples", opt->study_samples,
                  "samples of each --study evaluation, default 64");
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
