#include "engine/report/diagnosis_page.h"

#include <cmath>
#include <sstream>
#include <string>

#include "engine/report/report_contents.h"
#include "engine/report/report_plot.h"
#include "engine/report/result_sections.h"
#include "engine/results/result_io.h"

namespace poise::engine {
namespace {

using nlohmann::json;

std::string num(const json& v, int digits) {
  if (v.is_string()) return html_escape(v.get<std::string>());      // "inf"
  if (!v.is_number() || std::isnan(v.get<double>())) return "n/a";  // NaN: not estimated (JSON null)
  return format_significant(v.get<double>(), digits);
}

std::string text(const json& j, const char* key) { return html_escape(j.value(key, std::string())); }

std::string params_text(const json& params) {
  std::string s;
  for (const auto& [name, p] : params.items()) {
    const std::string unit = p.value("unit", std::string());
    if (!s.empty()) s += "<br>";
    s += html_escape(name) + " = " + num(p["value"], 4) + " &plusmn; " + num(p["se"], 2);
    if (!unit.empty()) s += ' ' + html_escape(unit);
  }
  return s;
}

std::string estimate_text(const json& e, const std::string& unit) {
  return "amplitude " + num(e["amplitude"], 5) + " &plusmn; " + num(e["se_amplitude"], 2) + " " + html_escape(unit) +
         ", phase " + num(e["phase_deg"], 5) + " &plusmn; " + num(e["se_phase_deg"], 2) + " deg, offset " +
         num(e["offset"], 4) + " &plusmn; " + num(e["se_offset"], 2) + " " + html_escape(unit);
}

std::string method_html(const json& d) {
  std::ostringstream h;
  h << "<p>Data: <code>" << text(d, "file") << "</code>, " << d.value("n_points", 0) << " points, torque in "
    << text(d, "unit") << "; time: " << (d.value("time_column", false) ? "column time_s" : "row order")
    << "; sweep: " << (d.value("sweep_column", false) ? "column sweep" : "none")
    << ".</p>\n<p>Base model (Yang et al. 2015, Eq. 22): M(theta) = MT_s sin(theta + b) + MK. Candidates: harmonics "
       "2.."
    << d.value("max_harmonic", 0)
    << ", time drift, K_T drift, direction offset, step, exponential settling, outliers, AR(1) errors, added by "
       "forward stepwise selection (F test; for AR(1) the one-sided (rho &gt; 0) restricted likelihood ratio; "
       "Holm-adjusted per round, alpha = "
    << num(d["alpha"], 3) << ", and &Delta;BIC &lt; 0).</p>\n";
  return h.str();
}

std::string findings_html(const json& d) {
  std::ostringstream h;
  h << "<h2 id='findings'>Findings</h2>\n";
  if (d["effects"].empty()) {
    h << "<p>No effect beyond Eq. 22 was found: the base model explains the data within its noise.</p>\n";
  } else {
    h << "<table><tr><th>#</th><th class='l'>effect</th><th class='l'>parameters (&plusmn; SE)</th><th>p</th>"
         "<th>Holm p</th><th>&Delta;BIC</th><th class='l'>possible causes</th></tr>\n";
    int i = 0;
    for (const auto& e : d["effects"]) {
      h << "<tr><td>" << ++i << "</td><td class='l'>" << text(e, "title") << "</td><td class='l'>"
        << params_text(e["params"]) << "</td><td>" << num(e["p_value"], 3) << "</td><td>" << num(e["p_adjusted"], 3)
        << "</td><td>" << num(e["delta_bic"], 3) << "</td><td class='l'>" << text(e, "causes") << "</td></tr>\n";
    }
    h << "</table>\n";
  }
  for (const auto& s : d["notes"]) h << "<p><i>Note: " << html_escape(s.get<std::string>()) << "</i></p>\n";
  const json& o = d["omnibus"];
  const bool flagged = o.value("unexplained_structure", false);
  h << "<h2 id='structure'>Unexplained structure</h2>\n<p>" << (flagged ? "<b>" : "") << text(o, "message")
    << (flagged ? "</b>" : "") << "</p>\n<ul>\n";
  for (const auto& t : o["tests"]) {
    const std::string note = t.value("note", std::string());
    h << "<li>" << text(t, "name") << ": "
      << (t.value("examined", false)
              ? "p = " + num(t["p_value"], 3) + (note.empty() ? "" : " (" + html_escape(note) + ")")
              : html_escape(note))
      << "</li>\n";
  }
  h << "</ul>\n";
  return h.str();
}

std::string separability_html(const json& d) {
  std::ostringstream h;
  h << "<h2 id='separability'>What this plan cannot tell apart</h2>\n<p>Plan: " << text(d, "plan") << ".</p>\n"
    << "<table><tr><th class='l'>candidate</th><th>r with the first harmonic</th><th>VIF against Eq. 22</th>"
       "<th class='l'>closest other candidate</th><th>r</th></tr>\n";
  for (const auto& c : d["collinearity"]) {
    h << "<tr><td class='l'>" << text(c, "candidate") << "</td><td>" << num(c["r_first_harmonic"], 3) << "</td><td>"
      << num(c["vif_base"], 3) << "</td><td class='l'>" << text(c, "most_collinear_with") << "</td><td>"
      << num(c["r_other"], 3) << "</td></tr>\n";
  }
  h << "</table>\n";
  for (const auto& a : d["ambiguous"]) {
    h << "<p>" << text(a, "why") << ".</p>\n<table><tr><th class='l'>reading</th><th>&Delta;BIC</th>"
      << "<th class='l'>unbalance estimate</th></tr>\n";
    for (const auto& rd : a["readings"]) {
      h << "<tr><td class='l'>" << text(rd, "effects") << "</td><td>" << num(rd["delta_bic"], 3)
        << "</td><td class='l'>" << estimate_text(rd["estimate"], d.value("unit", std::string())) << "</td></tr>\n";
    }
    h << "</table>\n<p>A plan that would separate them: " << text(a, "plan") << ".</p>\n";
  }
  for (const auto& n : d["not_identifiable"]) {
    h << "<p>Not identifiable from one test: <b>" << text(n, "name") << "</b>: " << text(n, "why") << ".</p>\n";
  }
  return h.str();
}

std::string before_after_html(const json& d) {
  const std::string u = d.value("unit", std::string());
  std::ostringstream h;
  const auto row = [&](const std::string& name, const json& a, const json& b, const char* key,
                       const std::string& unit) {
    h << "<tr><td class='l'>" << name << "</td><td>" << num(a[key], 5) << "</td><td>" << num(b[key], 5)
      << "</td><td class='l'>" << html_escape(unit) << "</td></tr>\n";
  };
  h << "<h2 id='before-after'>Before and after</h2>\n<table><tr><th></th><th>base fit</th><th>final model</th>"
       "<th class='l'>unit</th></tr>\n<tr><td class='l'>rmse</td><td>"
    << num(d["rmse_before"], 4) << "</td><td>" << num(d["rmse_after"], 4) << "</td><td class='l'>" << html_escape(u)
    << "</td></tr>\n";
  const json& eb = d["estimate_before"];
  const json& ea = d["estimate_after"];
  row("amplitude MT_s", eb, ea, "amplitude", u);
  row("SE amplitude", eb, ea, "se_amplitude", u);
  row("phase b", eb, ea, "phase_deg", "deg");
  row("SE phase", eb, ea, "se_phase_deg", "deg");
  row("offset MK", eb, ea, "offset", u);
  row("SE offset", eb, ea, "se_offset", u);
  if (d.contains("load")) {
    h << "<tr><th colspan='4' class='l'>against the known load " << num(d["load"]["torque"], 4) << " " << html_escape(u)
      << " at " << num(d["load"]["angle_deg"], 4) << " deg (estimate - load)</th></tr>\n";
    row("amplitude error", d["error_before"], d["error_after"], "amplitude", u);
    row("phase error", d["error_before"], d["error_after"], "phase_deg", "deg");
  }
  h << "</table>\n";
  return h.str();
}

std::string closed_loop_html(const json& d) {
  if (!d.contains("closed_loop")) return "";
  std::ostringstream h;
  h << "<h2 id='closed-loop'>The loop closed in the simulation model</h2>\n<p>" << text(d["closed_loop"], "sentence")
    << "</p>\n<ul>\n";
  for (const auto& [k, v] : d["closed_loop"]["overrides"].items()) {
    h << "<li><code>" << html_escape(k) << " = " << html_escape(v.is_string() ? v.get<std::string>() : v.dump())
      << "</code></li>\n";
  }
  h << "</ul>\n";
  return h.str();
}

}  // namespace

std::string diagnosis_report_html(const json& d, const std::filesystem::path& plot_svg, const std::string& plot_note) {
  std::ostringstream h;
  h << report_page_head("residual diagnosis of " + d.value("file", std::string()))
    << "<h1>Residual diagnosis of a static unbalance measurement</h1>\n"
    << answer_html(d.value("answer", std::string()), json::array()) << method_html(d) << findings_html(d)
    << separability_html(d) << before_after_html(d) << closed_loop_html(d) << "<h2 id='plot'>Plot</h2>\n";
  if (plot_note.empty()) {
    h << inline_svg(plot_svg,
                    "Upper panel: measured points, the base fit and the final model at each point. Middle "
                    "panel: residuals of both against the turntable angle (with AR(1) errors the final "
                    "residual is the innovation; a flagged outlier's residual is 0). Lower panel: the same "
                    "residuals in measurement order (against time_s where the table has it), where a drift, "
                    "a step or a period in time shows.");
  } else {
    h << "<p><b>" << html_escape(plot_note) << "</b></p>\n";
  }
  h << "<h2 id='tested'>Candidates tested in the last round, not added</h2>\n<ul>\n";
  for (const auto& s : d.value("tested", json::array())) h << "<li>" << html_escape(s.get<std::string>()) << "</li>\n";
  h << "</ul>\n<p><small>Files beside this page: <a href='diagnosis.json'>diagnosis.json</a>, "
       "<a href='plot.dat'>plot.dat</a>, <a href='plot.gp'>plot.gp</a>, <a href='plot.svg'>plot.svg</a>.</small></p>\n"
       "</body></html>\n";
  return with_contents(h.str());
}

}  // namespace poise::engine
