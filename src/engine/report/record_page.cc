#include "engine/report/record_page.h"

#include <sstream>

#include "engine/report/report_contents.h"
#include "engine/report/report_plot.h"
#include "engine/report/result_sections.h"
#include "engine/results/result_io.h"

namespace poise::engine {
namespace {

using nlohmann::json;

std::string record_num(const json& v, int digits) {
  return v.is_number() ? format_significant(v.get<double>(), digits) : std::string("n/a");
}

// d[key], or an empty array when d has no such member (a reference, never a temporary).
const json& listed(const json& d, const char* key) {
  static const json kEmpty = json::array();
  return d.contains(key) ? d[key] : kEmpty;
}

// d[key] as an object, or an empty object.
const json& fields(const json& d, const char* key) {
  static const json kEmpty = json::object();
  return d.contains(key) ? d[key] : kEmpty;
}

std::string value_se(const json& v, const std::string& unit, int digits = 4) {
  return record_num(v["value"], digits) + " &plusmn; " + record_num(v["se"], 2) + " " + html_escape(unit);
}

std::string reading_html(const json& d) {
  std::ostringstream h;
  h << "<h2 id='record'>The record</h2>\n<p>Motion: " << html_escape(d["motion"].value("description", ""))
    << ".</p>\n<ul>\n";
  for (const auto& r : listed(d, "reading")) h << "<li>" << html_escape(r.get<std::string>()) << "</li>\n";
  const json& t = fields(d, "time");
  if (t.contains("gaps") && t["median_step_s"].is_number()) {
    h << "<li>time: median step " << record_num(t["median_step_s"], 4) << " s; " << t["gaps"].get<int>() << " gap(s)";
    if (t["gaps"].get<int>() > 0) {
      h << " over " << record_num(t["gap_total_s"], 3) << " s, the largest " << record_num(t["gap_largest_s"], 3)
        << " s before line " << t["gap_largest_line"].get<long>();
    }
    h << "</li>\n";
  }
  h << "</ul>\n";
  return h.str();
}

std::string model_html(const json& d) {
  std::ostringstream h;
  h << "<h2 id='model'>Base model</h2>\n<table><tr><th class='l'>parameter</th><th>estimate &plusmn; SE</th></tr>\n";
  if (d.contains("offset_mNm")) {
    h << "<tr><td class='l'>M_0 (mean torque)</td><td>" << value_se(d["offset_mNm"], "mN*m") << "</td></tr>\n";
    if (d.contains("coulomb_mNm")) {
      h << "<tr><td class='l'>C (Coulomb friction)</td><td>" << value_se(d["coulomb_mNm"], "mN*m") << "</td></tr>\n"
        << "<tr><td class='l'>torque forward, M_0 + C</td><td>" << value_se(d["torque_forward_mNm"], "mN*m")
        << "</td></tr>\n<tr><td class='l'>torque backward, M_0 - C</td><td>"
        << value_se(d["torque_backward_mNm"], "mN*m") << "</td></tr>\n";
    }
  }
  for (const auto& [name, p] : fields(d, "base_model").items()) {
    h << "<tr><td class='l'>" << html_escape(name) << "</td><td>" << value_se(p, p.value("unit", "")) << "</td></tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

std::string map_html(const json& d) {
  std::ostringstream h;
  h << "<h2 id='map'>Cogging map</h2>\n";
  const json& map = listed(d, "cogging_map");
  if (map.empty()) {
    h << "<p>No cogging order stands out of the residual's noise.</p>\n";
    return h.str();
  }
  h << "<p>Every significant order, in the order found (amplitude T and phase psi of the motor's torque T sin(N phi "
       "+ psi), one standard error; orders closer than the resolution are not told apart).</p>\n"
       "<table><tr><th>order N</th><th>amplitude T</th><th>phase psi</th><th>resolution</th><th>p</th>"
       "<th>adjusted p</th><th>&Delta;BIC</th></tr>\n";
  for (const auto& o : map) {
    h << "<tr><td>" << o["order"].get<int>() << "</td><td>" << value_se(o["amplitude_mNm"], "mN*m") << "</td><td>"
      << value_se(o["phase_rad"], "rad") << "</td><td>&plusmn;" << record_num(o["order_resolution"], 2) << "</td><td>"
      << record_num(o["p_value"], 2) << "</td><td>" << record_num(o["p_adjusted"], 2) << "</td><td>"
      << record_num(o["delta_bic"], 3) << "</td></tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

std::string effects_html(const json& d) {
  std::ostringstream h;
  const json& effects = listed(d, "effects");
  if (!effects.empty()) {
    h << "<h2 id='effects'>Effects</h2>\n<table><tr><th class='l'>effect</th><th class='l'>parameters</th><th>p</th>"
         "<th>adjusted p</th><th>&Delta;BIC</th><th class='l'>possible causes</th></tr>\n";
    for (const auto& e : effects) {
      std::string params;
      for (const auto& [name, p] : fields(e, "params").items()) {
        params += (params.empty() ? "" : "<br>") + html_escape(name) + " = " + value_se(p, p.value("unit", ""));
      }
      std::string name = e.value("name", "");
      if (e.contains("order")) name += " of order " + std::to_string(e["order"].get<int>());
      h << "<tr><td class='l'>" << html_escape(name) << "</td><td class='l'>" << params << "</td><td>"
        << record_num(e["p_value"], 2) << "</td><td>" << record_num(e["p_adjusted"], 2) << "</td><td>"
        << record_num(e["delta_bic"], 3) << "</td><td class='l'>" << html_escape(e.value("causes", ""))
        << "</td></tr>\n";
    }
    h << "</table>\n";
  }
  h << "<h2 id='limits'>What this record cannot show</h2>\n<ul>\n";
  for (const auto& n : listed(d, "not_identifiable")) {
    h << "<li><b>" << html_escape(n.value("name", "")) << "</b>: " << html_escape(n.value("why", "")) << "</li>\n";
  }
  for (const auto& s : listed(d, "outside_physics")) {
    h << "<li><b>outside physics (not a finding)</b>: " << html_escape(s.get<std::string>()) << "</li>\n";
  }
  h << "</ul>\n";
  return h.str();
}

std::string residual_html(const json& d) {
  std::ostringstream h;
  h << "<h2 id='residual'>Residual</h2>\n<p>Torque residual RMS: " << record_num(d["rmse_before_mNm"], 4)
    << " mN*m with the base model, " << record_num(d["rmse_after_mNm"], 4) << " mN*m with every effect found";
  const json& steps = listed(d, "steps");
  if (!steps.empty()) {
    h << " (after each: ";
    bool first = true;
    for (const auto& s : steps) {
      h << (first ? "" : ", ") << html_escape(s.value("effect", "")) << " " << record_num(s["rmse_mNm"], 4);
      first = false;
    }
    h << " mN*m)";
  }
  h << ".</p>\n";
  return h.str();
}

}  // namespace

std::string record_report_html(const json& d, const std::vector<std::filesystem::path>& figures,
                               const std::string& note) {
  std::ostringstream h;
  h << report_page_head("Diagnosis of a raw record") << "<h1>Diagnosis of " << html_escape(d.value("file", "a record"))
    << "</h1>\n"
    << answer_html(d.value("answer", std::string()), json::array()) << reading_html(d) << model_html(d) << map_html(d);
  if (!figures.empty()) h << inline_svg(figures.front(), "Cogging map: amplitude against order, one standard error");
  h << effects_html(d) << residual_html(d);
  if (figures.size() > 1) h << inline_svg(figures[1], "Torque residual against angle, before and after the effects");
  if (!note.empty()) h << "<p><i>Figures: " << html_escape(note) << "</i></p>\n";
  h << "</body></html>\n";
  return with_contents(h.str());
}

}  // namespace poise::engine
