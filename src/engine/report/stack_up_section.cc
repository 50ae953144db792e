// The report's "Worst case, RSS and Monte Carlo" section (engine/run/stack_up.h), read from
// summary.json's "stack_up".
#include <string>

#include "core/format.h"
#include "engine/results/result_io.h"
#include "engine/run/stack_up.h"

namespace poise::engine {
namespace {
using nlohmann::json;

std::string number(const json& v) { return v.is_number() ? significant(v.get<double>(), 5) : "&ndash;"; }

std::string row(const std::string& what, const json& lo, const json& hi, const std::string& spread) {
  return "<tr><td class='l'>" + what + "</td><td>" + number(lo) + "</td><td>" + number(hi) + "</td><td>" + spread +
         "</td></tr>\n";
}

std::string with_interval(const json& e) {
  if (!e.is_object()) return "&ndash;";
  std::string s = number(e["value"]);
  if (e.contains("ci95")) s += " <small>[" + number(e["ci95"][0]) + ", " + number(e["ci95"][1]) + "]</small>";
  return s;
}

// One output's methods side by side, then each input's share under each.
std::string output_section(const std::string& name, const json& o, const json& inputs) {
  const std::string unit = o["unit"].get<std::string>();
  std::string h = "<h3><code>" + html_escape(name) + "</code> [" + html_escape(unit) + "]</h3>\n";
  h += "<table><tr><th class='l'>method</th><th>min</th><th>max</th><th>half-width or sd</th></tr>\n";
  h += row("nominal (every input at its mean)", o["nominal"], o["nominal"], "");
  if (o.contains("worst_case")) {
    const json& w = o["worst_case"];
    std::string note = number(json(0.5 * (w["max"].get<double>() - w["min"].get<double>())));
    if (w["corners_without_value"].get<std::size_t>() > 0) {
      note += " <small>(" + std::to_string(w["corners_without_value"].get<std::size_t>()) +
              " corners without value)</small>";
    }
    h += row("worst case: extremes over the " + std::to_string(w["corners"].get<std::size_t>()) + " corners", w["min"],
             w["max"], note);
  }
  const json& lin = o["worst_case_linear"];
  h += row("worst case, linearised", lin["min"], lin["max"], number(lin["half_width"]));
  const json& rss = o["rss"];
  h += row("RSS of the tolerances", rss["min"], rss["max"],
           number(rss["half_width"]) + " <small>(first-order sd " + number(rss["sd_first_order"]) + ")</small>");
  if (o.contains("monte_carlo")) {
    const json& mc = o["monte_carlo"];
    h += row("Monte Carlo: p0.135 to p99.865 (sample min " + number(mc["min"]) + ", max " + number(mc["max"]) + ")",
             mc["p0_135"], mc["p99_865"],
             "sd " + number(mc["sd"]) + " <small>(mean " + number(mc["mean"]) + ")</small>");
  }
  h += "</table>\n";
  if (o.contains("capability")) {
    const json& c = o["capability"];
    h += "<p>Against the specification [" + html_escape(c["as_written"][0].get<std::string>()) + ", " +
         html_escape(c["as_written"][1].get<std::string>()) + "]: Cp " + with_interval(c.value("cp", json())) +
         ", Cpk " + with_interval(c.value("cpk", json())) + ", " + with_interval(c["ppm_outside"]) +
         " parts per million outside (95% intervals; " + html_escape(c["note"].get<std::string>()) + ").</p>\n";
  }
  const json& shares = o["contributions_percent"];
  const bool has_mc = shares.contains("monte_carlo");
  h += "<table><tr><th class='l'>input</th><th>limits</th><th>sensitivity [" + html_escape(unit) +
       " per unit]</th><th>% of worst case</th><th>% of RSS variance</th>" +
       (has_mc ? "<th>% of Monte Carlo variance</th>" : "") + "</tr>\n";
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    h += "<tr><td class='l'><code>" + html_escape(inputs[i]["name"].get<std::string>()) + "</code></td><td>" +
         number(inputs[i]["lower"]) + " to " + number(inputs[i]["upper"]) + "</td><td>" +
         number(o["sensitivities"][i]) + "</td><td>" + number(shares["worst_case"][i]) + "</td><td>" +
         number(shares["rss"][i]) + "</td>" + (has_mc ? "<td>" + number(shares["monte_carlo"][i]) + "</td>" : "") +
         "</tr>\n";
  }
  h += "</table>\n";
  if (has_mc) {
    h += "<p><small>Monte Carlo shares: squared standardized regression coefficients; their sum R<sup>2</sup> = " +
         number(shares["monte_carlo_r2"]) + " (1 for an output linear in its inputs).</small></p>\n";
  }
  return h;
}

}  // namespace

std::string stack_up_html(const json& stack_up) {
  if (!stack_up.is_object()) return "";
  std::string h =
      "<h2>Worst case, RSS and Monte Carlo</h2>\n<p>Each output over the box of the inputs' drawing limits: " +
      html_escape(stack_up["worst_case_method"].get<std::string>()) + "; RSS " +
      html_escape(stack_up["rss_method"].get<std::string>()) +
      "; Monte Carlo from this run's samples. Limits and figures in the units of samples.csv.</p>\n";
  for (const auto& [name, o] : stack_up["outputs"].items()) h += output_section(name, o, stack_up["inputs"]);
  return h;
}

}  // namespace poise::engine
