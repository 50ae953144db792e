#include "engine/report/budget_page.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/format.h"
#include "engine/report/budget_numbers.h"
#include "engine/report/report_contents.h"
#include "engine/report/report_plot.h"
#include "engine/report/result_sections.h"
#include "engine/results/result_io.h"

namespace poise::engine {
namespace {

using nlohmann::json;

double nice_step(double span) {
  const double raw = span / 6.0;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    if (m * p >= raw) return m * p;
  }
  return 10 * p;
}

std::string verdict_cell(const std::string& v) {
  const char* color = v == "agrees" ? "#1b7837" : v == "disagrees" ? "#b2182b" : "#555";
  // budget.json's verdict tokens in words (the JSON keeps the tokens).
  const std::string words = v == "no_declared" ? "none declared" : v == "given" ? "given, not recomputed" : v;
  return "<td style='color:" + std::string(color) + ";font-weight:bold'>" + html_escape(words) + "</td>";
}

std::string rel_cell(const json& it) {
  if (!it.contains("relative_difference") || it["relative_difference"].is_null()) return "<td></td>";
  return "<td>" + signed_percent(it["relative_difference"].get<double>()) + "</td>";
}

std::string inputs_of(const json& l) {
  if (!l.contains("tolerance")) return "";
  std::string s = l["tolerance"].get<std::string>();
  if (l.contains("lever")) s += " over " + l["lever"].get<std::string>();
  s += ", " + l["distribution"].get<std::string>() + ", " + l["tolerance_is"].get<std::string>();
  if (l["gain"].get<std::string>() != "1") s += ", gain " + l["gain"].get<std::string>();
  if (l.contains("propagation")) s += ", propagation " + l["propagation"].get<std::string>();
  return s;
}

/// A point of the field ({"k": 0.4, "yaw": -29.999999999999996}) as "k 0.4, yaw -30".
std::string point_text(const json& at) {
  if (!at.is_object()) return at.dump();
  std::string s;
  for (const auto& [k, v] : at.items()) {
    s += (s.empty() ? "" : ", ") + k + " " + (v.is_number() ? format_significant(v.get<double>(), 6) : v.dump());
  }
  return s;
}

}  // namespace

namespace {

// The chart's frame: the plot area inside the margins (the legend sits below the axis label,
// outside the data: up to 4 rows of 16 px) and the value and probability scales.
struct ChartFrame {
  double W = 780, H = 472, L = 60, R = 20, T = 20, B = 122;
  double pw = W - L - R, ph = H - T - B;
  double xmax = 1.0;
  double X(double v) const { return L + pw * v / xmax; }
  double Y(double p) const { return T + ph * (1.0 - p); }
};

void axes_svg(std::ostringstream& s, const ChartFrame& f, const json& j, const std::vector<double>& mc,
              const std::string& unit) {
  s << "<rect x='" << f.L << "' y='" << f.T << "' width='" << f.pw << "' height='" << f.ph
    << "' fill='none' stroke='#444'/>\n";
  const double step = nice_step(f.xmax);
  for (double t = 0; t <= f.xmax + 1e-12; t += step) {
    s << "<line x1='" << fixed(f.X(t), 2) << "' y1='" << f.T + f.ph << "' x2='" << fixed(f.X(t), 2) << "' y2='"
      << f.T + f.ph + 5 << "' stroke='#444'/><text x='" << fixed(f.X(t), 2) << "' y='" << f.T + f.ph + 18
      << "' text-anchor='middle'>" << significant(std::abs(t) < 1e-12 ? 0.0 : t, 6) << "</text>\n";
  }
  for (int k = 0; k <= 4; ++k) {
    const double p = k / 4.0;
    s << "<line x1='" << f.L - 5 << "' y1='" << fixed(f.Y(p), 2) << "' x2='" << f.L << "' y2='" << fixed(f.Y(p), 2)
      << "' stroke='#444'/><text x='" << f.L - 8 << "' y='" << fixed(f.Y(p) + 4, 2) << "' text-anchor='end'>" << p
      << "</text>\n";
  }
  s << "<text x='" << f.L + f.pw / 2 << "' y='" << f.T + f.ph + 38 << "' text-anchor='middle'>"
    << html_escape(mc.empty() ? "combined figure" : j["monte_carlo"]["output"].get<std::string>()) << " ["
    << html_escape(unit) << "]</text>\n";
  s << "<text transform='rotate(-90)' x='" << -(f.T + f.ph / 2) << "' y='16' text-anchor='middle'>"
    << (mc.empty() ? "" : "fraction of units at or below (CDF)") << "</text>\n";
}

// Histogram (scaled to 0.9 of the height) and empirical CDF of the Monte Carlo, its quantile
// at the confidence with the 95% interval shaded.
void monte_carlo_svg(std::ostringstream& s, const ChartFrame& f, const json& j, const std::vector<double>& mc) {
  const int bins = 50;
  std::vector<double> count(bins, 0.0);
  for (double v : mc) count[std::min(bins - 1, static_cast<int>(v / f.xmax * bins))] += 1;
  const double top = *std::max_element(count.begin(), count.end());
  for (int b = 0; b < bins; ++b) {
    const double h = 0.9 * count[b] / top;
    s << "<rect x='" << fixed(f.X(f.xmax * b / bins), 2) << "' y='" << fixed(f.Y(h), 2) << "' width='"
      << fixed(f.pw / bins, 2) << "' height='" << fixed(f.ph * h, 2)
      << "' fill='#c6dbef' stroke='#fff' stroke-width='0.5'/>\n";
  }
  s << "<polyline fill='none' stroke='#08519c' stroke-width='1.5' points='";
  const std::size_t n = mc.size(), every = std::max<std::size_t>(1, n / 800);
  for (std::size_t i = 0; i < n; i += every) {
    s << fixed(f.X(mc[i]), 2) << ',' << fixed(f.Y(static_cast<double>(i + 1) / static_cast<double>(n)), 2) << ' ';
  }
  s << fixed(f.X(mc.back()), 2) << ',' << fixed(f.Y(1.0), 2) << "'/>\n";
  const json& m = j["monte_carlo"];
  const double q = m["value"].get<double>(), p = m["quantile"].get<double>();
  if (!m["ci95"][0].is_null() && !m["ci95"][1].is_null()) {
    const double lo = m["ci95"][0].get<double>(), hi = m["ci95"][1].get<double>();
    s << "<rect x='" << fixed(f.X(lo), 2) << "' y='" << f.T << "' width='" << fixed(std::max(1.0, f.X(hi) - f.X(lo)), 2)
      << "' height='" << f.ph << "' fill='#08519c' opacity='0.15'/>\n";
  }
  s << "<line x1='" << fixed(f.X(q), 2) << "' y1='" << f.T << "' x2='" << fixed(f.X(q), 2) << "' y2='" << f.T + f.ph
    << "' stroke='#08519c' stroke-width='2'/>\n<line x1='" << f.L << "' y1='" << fixed(f.Y(p), 2) << "' x2='"
    << f.L + f.pw << "' y2='" << fixed(f.Y(p), 2) << "' stroke='#08519c' stroke-dasharray='2,3'/>\n";
}

struct LegendEntry {
  const char* color;
  const char* dash;
  std::string text;
};

// The budget's lines (dashed: at its level; solid: at the confidence), the requirement
// (dash-dot: not by hue alone), and the legend below the axis.
void budget_lines_svg(std::ostringstream& s, const ChartFrame& f, const json& j, bool with_mc) {
  const json& c = j["combined"];
  const json& a = j["at_confidence"];
  const json& req = j["budget"]["requirement"];
  auto vline = [&](double v, const char* color, const char* dash, double width) {
    s << "<line x1='" << fixed(f.X(v), 2) << "' y1='" << f.T << "' x2='" << fixed(f.X(v), 2) << "' y2='" << f.T + f.ph
      << "' stroke='" << color << "' stroke-width='" << width << "'"
      << (dash[0] ? std::string(" stroke-dasharray='") + dash + "'" : "") << "/>\n";
  };
  vline(c["least"].get<double>(), "#1b7837", "6,4", 1.5);
  vline(c["greatest"].get<double>(), "#1b7837", "6,4", 1.5);
  vline(a["least"].get<double>(), "#1b7837", "", 2.5);
  vline(a["greatest"].get<double>(), "#1b7837", "", 2.5);
  if (!req.is_null()) vline(req.get<double>(), "#b2182b", "10,3,2,3", 2);
  std::vector<LegendEntry> legend = {
      {"#1b7837", "6,4", "budget least/greatest at " + j["budget"]["level"].get<std::string>()},
      {"#1b7837", "", "budget least/greatest at confidence " + budget_number(a["confidence"])}};
  if (!req.is_null()) legend.push_back({"#b2182b", "10,3,2,3", "requirement"});
  if (with_mc)
    legend.push_back({"#08519c", "", "Monte Carlo CDF; quantile at the confidence, its 95% interval shaded"});
  for (std::size_t k = 0; k < legend.size(); ++k) {
    const double y = f.T + f.ph + 62 + 16 * static_cast<double>(k);
    s << "<line x1='" << f.L + 10 << "' y1='" << y - 4 << "' x2='" << f.L + 40 << "' y2='" << y - 4 << "' stroke='"
      << legend[k].color << "' stroke-width='2'"
      << (legend[k].dash[0] ? std::string(" stroke-dasharray='") + legend[k].dash + "'" : "") << "/><text x='"
      << f.L + 46 << "' y='" << y << "'>" << html_escape(legend[k].text) << "</text>\n";
  }
}

}  // namespace

std::string budget_plot_svg(const json& j, const std::vector<double>& mc) {
  const std::string unit = j["budget"]["unit"].get<std::string>();
  const json& req = j["budget"]["requirement"];
  ChartFrame f;
  f.xmax = std::max({j["combined"]["greatest"].get<double>(), j["at_confidence"]["greatest"].get<double>(), 1e-300});
  if (!req.is_null()) f.xmax = std::max(f.xmax, req.get<double>());
  if (!mc.empty()) f.xmax = std::max(f.xmax, mc.back());
  f.xmax *= 1.05;
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << f.W << "' height='" << f.H << "' viewBox='0 0 " << f.W
    << ' ' << f.H << "' font-family='sans-serif' font-size='12'>\n";
  axes_svg(s, f, j, mc, unit);
  if (!mc.empty()) monte_carlo_svg(s, f, j, mc);
  budget_lines_svg(s, f, j, !mc.empty());
  s << "</svg>\n";
  return s.str();
}

namespace {

std::string lines_html(const json& j, const std::string& unit) {
  std::ostringstream h;
  h << "<h2 id='lines'>Lines</h2>\n<table><tr><th class='l'>line</th><th class='l'>kind</th><th class='l'>inputs</th>"
    << "<th>recomputed</th><th>declared</th><th>difference</th><th>verdict</th><th class='l'>likely slip</th></tr>\n";
  for (const auto& l : j["lines"]) {
    const bool given = l["verdict"] == "given";
    h << "<tr><td class='l'>" << html_escape(l["name"].get<std::string>()) << "</td><td class='l'>"
      << html_escape(l["kind"].get<std::string>()) << "</td><td class='l'>" << html_escape(inputs_of(l))
      << (l.contains("model_key") ? " <small>(" + html_escape(l["model_key"].get<std::string>()) + ")</small>" : "")
      << "</td><td>"
      << html_escape(given ? "given " + budget_number(l["value"]) + " " + unit : recomputed_text(l, unit))
      << "</td><td>" << html_escape(declared_text(l["declared"], unit)) << "</td>" << rel_cell(l)
      << verdict_cell(l["verdict"].get<std::string>()) << "<td class='l'>"
      << html_escape(l.value("slip", std::string())) << "</td></tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

std::string groups_html(const json& j, const std::string& unit) {
  if (j["groups"].empty()) return "";
  std::ostringstream h;
  h << "<h2 id='groups'>Groups (sub-totals)</h2>\n<table><tr><th class='l'>group</th><th class='l'>members, rule</th>"
    << "<th>recomputed</th><th>declared</th><th>difference</th><th>from the members' declared</th><th>verdict</th>"
    << "<th class='l'>likely slip</th></tr>\n";
  for (const auto& g : j["groups"]) {
    std::string members;
    for (const auto& m : g["members"]) members += (members.empty() ? "" : ", ") + m.get<std::string>();
    members += "; " + g["combination"].get<std::string>();
    if (g.contains("propagation")) members += "; propagation " + g["propagation"].get<std::string>();
    std::string from;
    if (g.contains("from_members_declared")) {
      from = budget_number(g["from_members_declared"]["least"]) + " to " +
             budget_number(g["from_members_declared"]["greatest"]);
    }
    h << "<tr><td class='l'>" << html_escape(g["name"].get<std::string>()) << "</td><td class='l'>"
      << html_escape(members) << "</td><td>" << html_escape(recomputed_text(g, unit)) << "</td><td>"
      << html_escape(declared_text(g["declared"], unit)) << "</td>" << rel_cell(g) << "<td>" << html_escape(from)
      << "</td>" << verdict_cell(g["verdict"].get<std::string>()) << "<td class='l'>"
      << html_escape(g.value("slip", std::string())) << "</td></tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

std::string combination_html(const json& j, const std::string& unit) {
  const json& b = j["budget"];
  const json& c = j["combined"];
  const json& a = j["at_confidence"];
  std::ostringstream h;
  h << "<h2 id='combination'>Combination</h2>\n<table><tr><th class='l'>figure</th><th>least</th><th>greatest</th>"
    << "<th class='l'>note</th></tr>\n<tr><td class='l'>combined at " << html_escape(c["level"].get<std::string>())
    << " by " << html_escape(c["combination"].get<std::string>()) << "</td><td>" << budget_number(c["least"])
    << "</td><td>" << budget_number(c["greatest"]) << "</td><td class='l'>least at "
    << html_escape(point_text(c["least_at"])) << ", greatest at " << html_escape(point_text(c["greatest_at"]))
    << "</td></tr>\n";
  if (!c["declared"].is_null()) {
    h << "<tr><td class='l'>declared</td><td colspan='2'>" << html_escape(declared_text(c["declared"], unit))
      << "</td><td class='l'><b>" << html_escape(c["verdict"].get<std::string>()) << "</b> "
      << html_escape(c.value("slip", std::string())) << "</td></tr>\n";
  }
  if (c.contains("from_declared")) {
    h << "<tr><td class='l'>the declared entries, combined</td><td>" << budget_number(c["from_declared"]["least"])
      << "</td><td>" << budget_number(c["from_declared"]["greatest"]) << "</td><td></td></tr>\n";
  }
  if (c.contains("in_pixels")) {
    h << "<tr><td class='l'>in pixels</td><td>" << budget_number(c["least_px"]) << "</td><td>"
      << budget_number(c["greatest_px"]) << "</td><td class='l'>declared "
      << html_escape(declared_text(c["in_pixels"]["declared"], "px")) << ": <b>"
      << html_escape(c["in_pixels"]["verdict"].get<std::string>()) << "</b></td></tr>\n";
  }
  h << "<tr><td class='l'>at confidence " << budget_number(a["confidence"]) << " (random lines x "
    << budget_number(a["random_scale"]) << ", normal two-sided multiple " << budget_number(a["multiple"])
    << ")</td><td>" << budget_number(a["least"]) << "</td><td>" << budget_number(a["greatest"])
    << "</td><td class='l'>";
  if (!j["requirement_met"].is_null()) {
    h << "requirement " << budget_number(b["requirement"]) << " " << html_escape(unit) << ": "
      << (j["requirement_met"].get<bool>() ? "met" : "not met") << " by the combination rule alone (the answer above "
      << "decides on the Monte Carlo)";
  }
  h << "</td></tr>\n</table>\n<p><small>Figures in " << html_escape(unit) << ".</small></p>\n";
  return h.str();
}

std::string monte_carlo_html(const json& j, const std::string& unit, const std::vector<double>& mc) {
  const json& a = j["at_confidence"];
  std::ostringstream h;
  h << "<h2 id='monte-carlo'>The budget against the Monte Carlo</h2>\n";
  if (!j["monte_carlo"].is_null()) {
    const json& m = j["monte_carlo"];
    h << "<p>Monte Carlo of <code>" << html_escape(m["model"].get<std::string>()) << "</code> (" << m["samples"]
      << " independent samples, " << m["failures"] << " failed, seed " << m["seed"]
      << "): " << html_escape(m["output"].get<std::string>()) << " at " << budget_number(m["quantile"]) << " is "
      << budget_number(m["value"]) << " " << html_escape(unit) << " (95% interval " << budget_number(m["ci95"][0])
      << " to " << budget_number(m["ci95"][1]) << "). The budget's greatest at that confidence, "
      << budget_number(a["greatest"]) << " " << html_escape(unit) << ", is <b>"
      << html_escape(j["budget_vs_monte_carlo"].get<std::string>()) << "</b>"
      << (j["budget_vs_monte_carlo_decided"].get<bool>() ? "" : " (inside the Monte Carlo's 95% interval: not decided)")
      << ".</p>\n";
  } else {
    h << "<p>The budget names no model: no Monte Carlo beside it.</p>\n";
  }
  h << budget_plot_svg(j, mc);
  if (!j["unmapped_model_tolerances"].empty()) {
    h << "<p>Model tolerances no line covers (sampled by the Monte Carlo, absent from the budget):";
    for (const auto& k : j["unmapped_model_tolerances"])
      h << " <code>" << html_escape(k.get<std::string>()) << "</code>";
    h << "</p>\n";
  }
  for (const auto& k : j["unknown_model_keys"]) {
    h << "<p><b>Warning</b>: " << html_escape(k["in"].get<std::string>()) << " names <code>"
      << html_escape(k["key"].get<std::string>()) << "</code>, which the model does not have.</p>\n";
  }
  return h.str();
}

}  // namespace

std::string budget_report_html(const json& j, const std::vector<double>& mc) {
  const json& b = j["budget"];
  const std::string unit = b["unit"].get<std::string>();
  const std::string title =
      b["title"].get<std::string>().empty() ? b["name"].get<std::string>() : b["title"].get<std::string>();
  std::ostringstream h;
  h << report_page_head("budget " + b["name"].get<std::string>()) << "<h1>" << html_escape(title) << "</h1>\n"
    << answer_html(j.value("answer", std::string()),
                   j["requirement_verdict"].is_null() ? json::array() : json::array({j["requirement_verdict"]}))
    << "<p>Budget <code>" << html_escape(b["file"].get<std::string>()) << "</code>: contributions in "
    << html_escape(unit) << " at " << html_escape(b["level"].get<std::string>()) << ", combined by "
    << html_escape(b["combination"].get<std::string>()) << ". Every line is recomputed from its inputs (sigma of the "
    << "tolerance by its distribution and tolerance_is, over the lever, times the gain, at the level); a declared "
    << "figure agrees when it is within 1% of the recomputed one.</p>\n"
    << lines_html(j, unit) << groups_html(j, unit) << combination_html(j, unit) << monte_carlo_html(j, unit, mc);
  if (!b["notes"].get<std::string>().empty()) {
    h << "<h2 id='notes'>Notes of the budget (its author's text)</h2>\n<pre>"
      << html_escape(b["notes"].get<std::string>()) << "</pre>\n";
  }
  if (!b["source"].get<std::string>().empty()) {
    h << "<p><small>Source: " << html_escape(b["source"].get<std::string>()) << "</small></p>\n";
  }
  h << "</body></html>\n";
  return with_contents(h.str());
}

}  // namespace poise::engine
