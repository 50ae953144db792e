// The files of `poise diagnose --out DIR` besides diagnosis.json: plot.dat, plot.gp and
// plot.svg (gnuplot), and report.html.
#include <algorithm>
#include <numeric>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "cli/diagnose_output.h"
#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"

namespace poise::cli::diagnose_detail {
namespace fs = std::filesystem;
namespace est = poise::estimators;
using nlohmann::json;

namespace {

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

}  // namespace

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
  engine::write_file_atomic((dir / "plot.dat").string(), dat.str());
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
  engine::write_file_atomic((dir / "plot.gp").string(), gp.str());
  std::string why;
  if (engine::run_gnuplot((dir / "plot.gp").string(), &why) && fs::exists(dir / "plot.svg")) {
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
  engine::write_file_atomic((dir / "report.html").string(), h.str());
}

}  // namespace poise::cli::diagnose_detail
