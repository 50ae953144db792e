#include "engine/report/result_sections.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "core/format.h"
#include "core/number_text.h"
#include "engine/report/report_figures.h"
#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"

#include "engine/results/requirements.h"
#include "engine/run/procedure_sweeps.h"

namespace poise::engine {
using nlohmann::json;

std::string references_html(const json& compared) {
  if (!compared.is_array() || compared.empty()) return "";
  std::ostringstream h;
  int validations = 0, agree = 0, targets = 0, undecided = 0;
  for (const auto& c : compared) {
    if (c["role"] == "calibration_target") {
      ++targets;
    } else if (c["verdict"] == "undecided") {
      ++undecided;
    } else {
      ++validations;
      agree += c["verdict"] == "agrees" ? 1 : 0;
    }
  }
  h << "<h2>Declared reference figures</h2>\n<p>";
  if (validations > 0) {
    h << agree << " of " << validations << " validation figure(s) agree with the simulation";
  } else {
    h << "No validation figure is decided";
  }
  if (undecided > 0) h << "; " << undecided << " validation figure(s) undecided (too few samples)";
  if (targets > 0) {
    h << "; " << targets << " calibration target(s) are shown for completeness: the model was tuned to them, "
      << "so they agree by construction and are not evidence";
  }
  h << ". Only figures the study and model files declare ([[reference]]) are compared.</p>\n"
    << "<table><tr><th class='l'>figure</th><th class='l'>role</th><th class='l'>source</th><th>reference</th>"
       "<th>simulated</th><th>where it falls</th><th class='l'>verdict</th></tr>\n";
  for (const auto& c : compared) {
    const std::string verdict = c["verdict"].get<std::string>();
    const std::string cls = verdict == "agrees"      ? "ok"
                            : verdict == "disagrees" ? "bad"
                            : verdict == "undecided" ? "close"
                                                     : "target";
    const std::string unit = c["unit"].get<std::string>();
    h << "<tr class='" << cls << "'><td class='l'>" << html_escape(c["name"].get<std::string>()) << "<br><small><code>"
      << html_escape(c["output"].get<std::string>()) << "</code>, " << html_escape(c["statistic"].get<std::string>())
      << "</small></td><td class='l'>" << (c["role"] == "validation" ? "validation" : "calibration target")
      << (c.contains("follows_from")
              ? "<br><small>tuned: " + html_escape(c["follows_from"].get<std::string>()) + "</small>"
              : std::string())
      << "</td><td class='l'>" << html_escape(c["source"].get<std::string>()) << "</td><td>"
      << significant_or(c["reference"].get<double>(), "&ndash;") << " " << html_escape(unit) << "</td><td>";
    if (c.contains("simulated")) {
      const auto& e = c["simulated"];
      h << (e["value"].is_number() ? significant_or(e["value"].get<double>(), "&ndash;") : "&ndash;") << " <small>["
        << (e["ci95"][0].is_number() ? significant_or(e["ci95"][0].get<double>(), "&ndash;") : "&ndash;") << ", "
        << (e["ci95"][1].is_number() ? significant_or(e["ci95"][1].get<double>(), "&ndash;") : "open") << "]</small>";
    } else {
      h << "distribution";
    }
    h << "</td><td>";
    if (c.contains("percentile")) {
      h << significant_or(100 * c["percentile"].get<double>(), "&ndash;", 3) << "th percentile";
    } else {
      h << "&ndash;";
    }
    h << "</td><td class='l'>"
      << (verdict == "calibration_target" ? std::string("calibration target (not a validation)")
          : verdict == "undecided"        ? "undecided: " + html_escape(c.value("why", std::string()))
                                          : verdict)
      << "</td></tr>\n";
  }
  h << "</table>\n<p><small>";
  h << "A reference that is one realisation (a measured campaign: statistic <i>sample</i>) agrees when it lies "
       "within the central 95% of the simulated distribution; a reference that is a figure of the distribution "
       "(mean, p95, ...) agrees when it lies within that figure's 95% interval (or the declared "
       "tolerance).</small></p>\n";
  return h.str();
}

std::string answer_html(const std::string& answer, const json& verdicts) {
  std::string h = "<p class='answer'><b>" + html_escape(answer) + "</b></p>\n";
  if (verdicts.empty()) return h;
  h += "<table><tr><th class='l'>requirement</th><th>value</th><th>lower bound</th><th>upper bound</th>"
       "<th>one-sided confidence</th><th class='l'>verdict</th></tr>\n";
  auto number = [](const json& x) {
    return x.is_number() ? format_significant(x.get<double>(), 4) : std::string("&ndash;");
  };
  for (const auto& v : verdicts) {
    const std::string unit = v["limit"]["unit"].get<std::string>();
    const bool upper_is_bound = v.value("bound_side", "upper") == "upper";
    const json none;
    const json& upper = upper_is_bound ? v.value("bound", none) : v.value("other_bound", none);
    const json& lower = upper_is_bound ? v.value("other_bound", none) : v.value("bound", none);
    h += "<tr><td class='l'>" + html_escape(requirement_text(v)) + "</td><td>" +
         (v["value"].is_number() ? html_escape(with_unit(v["value"].get<double>(), unit)) : "&ndash;") + "</td><td>" +
         number(lower) + "</td><td>" + number(upper) + "</td><td>" +
         format_significant(v["confidence"].get<double>(), 4) + "</td><td class='l'><b>" +
         html_escape(v["verdict"].get<std::string>()) + "</b>" +
         (v.contains("note") ? " <small>" + html_escape(v["note"].get<std::string>()) + "</small>" : "") +
         (v.contains("design_note") ? " <small>(" + html_escape(v["design_note"].get<std::string>()) + ")</small>"
                                    : "") +
         "</td></tr>\n";
  }
  return h + "</table>\n";
}

std::string sensitivity_html(const json& s) {
  auto f = [](const json& e) {
    if (!e["value"].is_number()) return std::string("&ndash;");
    const auto end = [](const json& x) { return x.is_number() ? x.get<double>() : NAN; };
    const std::string text = fmt::format("{:.3f} <small>[{:.3f}, {:.3f}]</small>", e["value"].get<double>(),
                                         end(e["ci95"][0]), end(e["ci95"][1]));
    // An index whose interval reaches zero is not told apart from no influence at all.
    const bool resolved = !(end(e["ci95"][0]) <= 0.0);
    return text + (resolved ? "" : " <small>(not resolved)</small>");
  };
  std::string h = "<h2>Which input drives each output (Sobol indices)</h2>\n<p>" +
                  html_escape(s["method"].get<std::string>()) + "; " +
                  std::to_string(s["base_rows"].get<std::size_t>()) + " base rows, " +
                  std::to_string(s["evaluations"].get<std::size_t>()) + " evaluations. " +
                  html_escape(s["reading"].get<std::string>()) +
                  ". Groups whose total index is below 0.01 at both ends are left out; "
                  "an index whose 95% interval reaches zero is marked not resolved (these samples do not tell it "
                  "apart from no influence).</p>\n";
  auto table = [&](const json& rows, const json& first_sum, const char* what) {
    std::string t =
        "<table><tr><th class='l'>" + std::string(what) + "</th><th>first order S</th><th>total ST</th></tr>\n";
    for (const auto& g : rows) {
      const json& hi = g["total"]["ci95"][1];
      if (hi.is_number() && hi.get<double>() < 0.01) continue;
      std::string name = html_escape(g["group"].get<std::string>());
      if (g.contains("columns") && g["columns"].get<std::size_t>() > 1) {
        name += " <small>(" + std::to_string(g["columns"].get<std::size_t>()) + " columns together)</small>";
      }
      t += "<tr><td class='l'>" + name + "</td><td>" + f(g["first"]) + "</td><td>" + f(g["total"]) + "</td></tr>\n";
    }
    return t + "<tr><td class='l'><i>sum of first order</i></td><td>" + f(first_sum) +
           "</td><td></td></tr>\n</table>\n";
  };
  for (const auto& [name, o] : s["outputs"].items()) {
    h += "<h3><code>" + html_escape(name) + "</code></h3>\n";
    if (!o["note"].get<std::string>().empty()) h += "<p>" + html_escape(o["note"].get<std::string>()) + "</p>\n";
    if (o.contains("tolerances")) {
      h += "<p>Per tolerance of the model file: the closed index of all its sampled columns together "
           "(amplitude and phase, each bearing), so that the indices of different tolerances do not overlap.</p>\n";
      h += table(o["tolerances"], o["tolerance_first_sum"], "tolerance");
      h += "<details><summary>Per sampled column</summary>\n" + table(o["indices"], o["first_sum"], "column") +
           "</details>\n";
    } else {
      h += table(o["indices"], o["first_sum"], "input");
    }
  }
  return h;
}

std::string convergence_html(const json& c) {
  std::string h = "<h2>How many samples each figure needed</h2>\n<p>" +
                  std::to_string(c["samples"].get<std::size_t>()) + " samples; intervals from " +
                  c["intervals"].get<std::string>() +
                  ". For each figure: its 95% interval's half-width relative to it, and the samples a &plusmn;1% and "
                  "a &plusmn;5% interval would need (half-width ~ 1/&radic;n).</p>\n";
  if (!c["until"].is_null()) {
    const json& u = c["until"];
    h += "<p><b>--until " + html_escape(u["target"].get<std::string>()) + "</b>: " +
         (u["met"].get<bool>() ? "met at " + std::to_string(u["met_at_samples"].get<std::size_t>()) + " samples"
                               : std::string("not met within the cap of ") +
                                     std::to_string(u["cap_samples"].get<std::size_t>()) + " samples") +
         " (" + std::to_string(u["checks"].size()) + " checks).</p>\n";
  }
  h += "<table><tr><th class='l'>output</th><th class='l'>figure</th><th>value</th><th>rel. half-width</th>"
       "<th>samples for &plusmn;5%</th><th>samples for &plusmn;1%</th></tr>\n";
  auto cell = [](const json& v) {
    return v.is_null() ? std::string("&ndash;") : significant_or(v.get<double>(), "&ndash;");
  };
  for (const auto& [name, o] : c["figures"].items()) {
    for (const auto& [stat, f] : o.items()) {
      h += "<tr><td class='l'><code>" + html_escape(name) + "</code></td><td class='l'>" + stat + "</td><td>" +
           significant_or(f["value"].get<double>(), "&ndash;") + "</td><td>" +
           (f["relative_half_width"].is_null()
                ? std::string("&ndash;")
                : significant_or(100 * f["relative_half_width"].get<double>(), "&ndash;") + "%") +
           "</td><td>" + cell(f["samples_for_5pct"]) + "</td><td>" + cell(f["samples_for_1pct"]) + "</td></tr>\n";
    }
  }
  h += "</table>\n";
  // One-sided and approximate intervals, said in words (summary.json: "ci95_note"), each note
  // once with the outputs it holds for.
  std::vector<std::pair<std::string, std::vector<std::string>>> grouped;  // stat: note -> outputs
  for (const auto& [name, o] : c["figures"].items()) {
    for (const auto& [stat, f] : o.items()) {
      if (!f.contains("ci95_note")) continue;
      const std::string key = stat + ": " + f["ci95_note"].get<std::string>();
      auto it = std::find_if(grouped.begin(), grouped.end(), [&](const auto& g) { return g.first == key; });
      if (it == grouped.end()) it = grouped.insert(grouped.end(), {key, {}});
      it->second.push_back(name);
    }
  }
  std::string notes;
  for (const auto& [key, names] : grouped) {
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + std::string("<code>") + html_escape(n) + "</code>";
    notes += "<li>" + html_escape(key) + " <small>(" + list + ")</small></li>\n";
  }
  if (!notes.empty())
    h += "<p>Intervals to read with care (an end shown as &ndash; does not exist):</p>\n<ul>\n" + notes + "</ul>\n";
  return h;
}

std::string contributions_html(const json& contributions, const json& requirements,
                               const std::vector<OutputSpec>& outputs, const std::filesystem::path& plots_dir,
                               bool plots) {
  if (!contributions.is_array() || contributions.empty() || !contributions[0].contains("outputs")) return "";
  // The statistics shown: those the requirements name, else p95 of the first output.
  const auto shown = shown_statistics(requirements, outputs, 1);
  const json& all = contributions[0];
  std::string h =
      "<h2>Which tolerance drives the error</h2>\n<p>The study re-run with one tolerance set to zero "
      "at a time (" +
      std::to_string(all["samples"].get<std::size_t>()) +
      " samples each, the same random "
      "numbers): the drop of a statistic is that tolerance's share of it.</p>\n";
  std::vector<std::string> figures;
  for (const auto& [name, stat] : shown) {
    if (!all["outputs"].contains(name) || !all["outputs"][name].contains(stat)) continue;
    const double base = all["outputs"][name][stat]["value"].get<double>();
    const std::string unit = all["outputs"][name]["unit"].get<std::string>();
    h += "<table><tr><th class='l'>tolerance set to zero</th><th>" + html_escape(stat + " of " + name) + " [" +
         html_escape(unit) + "]</th><th>drop</th></tr>\n";
    std::vector<std::pair<std::string, double>> bars;
    for (const auto& c : contributions) {
      const std::string without = c["without"].get<std::string>();
      if (c.contains("skipped")) {
        h += "<tr><td class='l'>" + html_escape(without) + "</td><td colspan='2'>" +
             html_escape(c["skipped"].get<std::string>()) + "</td></tr>\n";
        continue;
      }
      const double v = c["outputs"][name][stat]["value"].get<double>();
      h += "<tr><td class='l'>" + html_escape(without) + "</td><td>" + format_significant(v) + "</td><td>" +
           format_significant(base - v) + "</td></tr>\n";
      if (&c != &all) bars.emplace_back(without, base - v);
    }
    h += "</table>\n";
    std::sort(bars.begin(), bars.end(),
              [](const auto& a, const auto& b) { return std::abs(a.second) > std::abs(b.second); });
    std::string why;
    if (plots) {
      tornado_figure(plots_dir, "contributions_" + name + "_" + stat,
                     "Drop of " + stat + " of " + name + " without each tolerance", "drop [" + unit + "]", bars,
                     figures, why);
    }
  }
  return h + figures_html(plots_dir, figures);
}

std::string sweeps_html(const json& sweeps, const std::vector<OutputSpec>& outputs,
                        const std::filesystem::path& plots_dir, bool plots) {
  if (!sweeps.is_array() || sweeps.empty()) return "";
  std::string h =
      "<h2>Sweeps</h2>\n<p>Each value runs the same samples (common random numbers): the differences "
      "between values are the design's, not the sampling's. Intervals are 95%.</p>\n";
  for (std::size_t s = 0; s < sweeps.size(); ++s) {
    const json& sw = sweeps[s];
    const std::string param = sw["parameter"].get<std::string>();
    const std::string x_unit =
        as_written(sw["points"].empty() ? std::string() : sw["points"][0]["value"].get<std::string>()).second;
    // The outputs shown: those a requirement names (with its statistic), else the first two.
    const auto show =
        shown_statistics(sw["points"].empty() ? json::array() : sw["points"][0]["requirements"], outputs, 2);
    h += "<h3>" + html_escape(param) + "</h3>\n<table><tr><th>" + html_escape(param) + "</th>";
    for (const auto& [name, stat] : show) h += "<th>" + html_escape(stat + " of " + name) + "</th>";
    h += "<th>failed</th></tr>\n";
    for (const auto& p : sw["points"]) {
      h += "<tr><td>" + html_escape(p["value"].get<std::string>()) + "</td>";
      for (const auto& [name, stat] : show) {
        std::string cell = "&ndash;";
        if (p["outputs"].contains(name) && p["outputs"][name].contains(stat)) {
          const json& e = p["outputs"][name][stat];
          auto end = [&](int k) {
            return e["ci95"][k].is_number() ? std::optional<double>(e["ci95"][k].get<double>()) : std::nullopt;
          };
          const IntervalText t = interval_text(e["value"].get<double>(), end(0), end(1));
          cell = t.value + " " + html_escape(p["outputs"][name]["unit"].get<std::string>());
          if (!t.lo.empty() && !t.hi.empty()) cell += " <small>[" + t.lo + ", " + t.hi + "]</small>";
        }
        for (const auto& r : p["requirements"]) {
          if (r["output"] == name && r["statistic"] == stat)
            cell += " <b>" + html_escape(r["verdict"].get<std::string>()) + "</b>";
        }
        h += "<td>" + cell + "</td>";
      }
      h += "<td>" + std::to_string(p["failures"].get<std::size_t>()) + "</td></tr>\n";
    }
    h += "</table>\n";
    if (!plots) continue;
    std::vector<std::string> figures;
    std::string why;
    for (const auto& [name, stat] : show) {
      std::vector<SweepFigurePoint> pts;
      std::string unit;
      for (const auto& p : sw["points"]) {
        if (!p["outputs"].contains(name) || !p["outputs"][name].contains(stat)) continue;
        const json& e = p["outputs"][name][stat];
        unit = p["outputs"][name]["unit"].get<std::string>();
        pts.push_back({as_written(p["value"].get<std::string>()).first, e["value"].get<double>(),
                       e["ci95"][0].is_number() ? e["ci95"][0].get<double>() : NAN,
                       e["ci95"][1].is_number() ? e["ci95"][1].get<double>() : NAN});
      }
      std::vector<FigureLine> limits;
      if (!sw["points"].empty()) {
        for (const auto& r : sw["points"][0]["requirements"]) {
          if (r["output"] == name && r["statistic"] == stat) {
            limits.push_back({r["limit"]["value"].get<double>(),
                              std::string(r["at_most"].get<bool>() ? "at most " : "at least ") +
                                  r["limit"]["as_written"].get<std::string>(),
                              "#cc3311"});
          }
        }
      }
      // Axis and title in the field's words: the output's description, its statistic, its unit.
      std::string description = name;
      for (const auto& o : outputs) {
        if (o.name == name && !o.description.empty()) description = o.description;
      }
      const std::string label =
          statistic_label(stat) + " of " + description + (unit.empty() || unit == "1" ? "" : " [" + unit + "]");
      sweep_figure(plots_dir, "sweep" + std::to_string(s) + "_" + name + "_" + stat,
                   statistic_label(stat) + " of " + name + " against " + param,
                   param + (x_unit.empty() ? "" : " [" + x_unit + "]"), label, pts, limits, figures, why);
    }
    h += figures_html(plots_dir, figures);
    if (!why.empty()) h += "<p><small>" + html_escape(why) + "</small></p>\n";
  }
  return h;
}

}  // namespace poise::engine
