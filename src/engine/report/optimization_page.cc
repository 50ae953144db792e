#include "engine/report/optimization_page.h"

#include <optional>
#include <sstream>
#include <string>

#include "core/number_text.h"
#include "engine/report/report_contents.h"
#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"

namespace poise::engine {
namespace {

using nlohmann::json;

std::string str(const json& j, const char* key) { return html_escape(j.value(key, std::string())); }

std::string number(const json& v) { return v.is_number() ? short_number(v.get<double>()) : std::string("&ndash;"); }

std::string percent(const json& fraction) {
  return fraction.is_number() ? format_significant(100.0 * fraction.get<double>(), 3) + "%" : std::string("&ndash;");
}

/// "1.13 [1.01, 1.23]" of an object with value and optional lo, hi.
std::string ci_text(const json& e) {
  if (!e.contains("value") || !e["value"].is_number()) return number(e.value("value", json()));
  const auto end = [&](const char* k) {
    return e.contains(k) && e[k].is_number() ? std::optional<double>(e[k].get<double>()) : std::nullopt;
  };
  // The digits the interval supports (core/number_text.h), as every report writes them.
  const IntervalText t = interval_text(e["value"].get<double>(), end("lo"), end("hi"));
  std::string s = t.value;
  if (e.contains("lo") || e.contains("hi")) {
    s += " [" + (end("lo") ? t.lo : "?") + ", " + (end("hi") ? t.hi : "?") + "]";
  }
  return s;
}

/// A design as "parameter = value, ..." (its JSON object of texts).
std::string design_text(const json& x) {
  if (!x.is_object()) return html_escape(x.dump());
  std::string s;
  for (const auto& [k, v] : x.items()) {
    s +=
        (s.empty() ? "" : ", ") + html_escape(k) + " = " + html_escape(v.is_string() ? v.get<std::string>() : v.dump());
  }
  return s;
}

std::string check_table(const json& check) {
  std::ostringstream h;
  if (check["constraints"].empty()) {
    h << "<p>The study states no constraint: " << check["samples"] << " fresh samples (seed " << check["seed"] << "), "
      << check["failures"] << " failed (" << percent(check["failure_share"]) << ").</p>\n";
    return h.str();
  }
  h << "<table><tr><th class='l'>constraint</th><th>on fresh samples [95% CI]</th><th>stated bound</th><th>limit</th>"
       "<th class='l'>interval from</th><th class='l'>verdict</th></tr>\n";
  for (const auto& c : check["constraints"]) {
    h << "<tr><td class='l'>" << str(c, "name") << "</td><td>" << ci_text(c["interval"]) << "</td><td>"
      << (c.contains("bound_value") ? number(c["bound_value"]) : "") << "</td><td>"
      << (c["at_least"].get<bool>() ? "&ge; " : "&le; ") << number(c["limit"]) << "</td><td class='l'>"
      << str(c["interval"], "method") << "</td><td class='l'>" << str(c, "verdict") << "</td></tr>\n";
  }
  h << "</table>\n<p>" << check["samples"] << " fresh samples (seed " << check["seed"] << "), " << check["failures"]
    << " failed (" << percent(check["failure_share"]) << ")"
    << (check["failures_within_max_share"].get<bool>() ? "" : ", more than the study's max_failure_share") << ".</p>\n";
  return h.str();
}

std::string opening_html(const json& s) {
  const json& o = s["optimization"];
  const bool feasible = s.value("feasible", false), verified = s.value("verified", false);
  std::ostringstream h;
  h << "<p class='answer" << (verified ? "" : " bad") << "'><b>"
    << (!feasible  ? "No feasible design."
        : verified ? "Verified on fresh samples."
                   : "Design NOT verified on fresh "
                     "samples (exit status 3).")
    << "</b> " << str(s, "answer") << "</p>\n";
  h << "<p>Optimization <code>" << str(o, "file") << "</code> over the study <code>" << str(o, "study")
    << "</code>: " << str(o, "algorithm") << " (" << str(o, "algorithm_advice") << "), " << o["samples_per_evaluation"]
    << " samples per evaluation with common random numbers (seed " << o["seed"] << ")";
  if (o.value("replicate_size", 0) > 0) {
    h << ", intervals from randomized replicates of " << o["replicate_size"] << " samples";
  }
  h << "; an evaluation with more than " << percent(o["max_failure_share"])
    << " failed samples counts as failed.</p>\n";
  return h.str();
}

std::string nearest_html(const json& s) {
  const json& n = s["nearest_passing_design"];
  const json& o = s["optimization"];
  std::ostringstream h;
  h << "<h3 id='nearest'>Nearest design that passes</h3>\n";
  if (n.value("found", false)) {
    h << "<p>Found by tightening each constraint that did not pass by its excess over the limit, searching again "
         "from the optimum, checking on the same fresh samples and re-checking on "
      << o["verification_samples"] << " other fresh samples (seed " << o["recheck_seed"] << "): <b>" << str(n, "design")
      << "</b>.</p>\n"
      << check_table(n["recheck"]);
  } else {
    h << "<p>None found: " << str(n, "why") << ".</p>\n";
  }
  return h.str();
}

std::string spread_html(const json& s) {
  const json& spread = s["optimum_spread"];
  std::ostringstream h;
  h << "<h2 id='spread'>The optimum's own uncertainty</h2>\n";
  if (!spread.contains("variables")) {
    h << "<p>One search ([optimization] replicates = 1): the spread of the optimum over seeds was not measured.</p>\n";
    return h.str();
  }
  h << "<p>The search of the headline combination run with " << spread["searches"]
    << " independent seeds (the optimum is set by the draw as much as by the design): the spread of each variable "
       "and of the objective, and the step the answer is rounded to (the power of ten at or below the range).</p>\n"
       "<table><tr><th class='l'>variable</th><th>min</th><th>max</th><th>std</th><th>answer rounded to</th></tr>\n";
  const auto row = [&](const std::string& name, const json& v) {
    h << "<tr><td class='l'>" << name << "</td><td>" << number(v["min"]) << "</td><td>" << number(v["max"])
      << "</td><td>" << number(v["std"]) << "</td><td>" << number(v["supported_step"]) << "</td></tr>\n";
  };
  for (const auto& v : spread["variables"]) row(str(v, "parameter") + " [" + str(v, "unit") + "]", v);
  row("objective (own samples)", spread["objective"]);
  h << "</table>\n";
  return h.str();
}

std::string fresh_check_html(const json& s) {
  std::ostringstream h;
  h << "<h2 id='fresh-check'>Fresh-sample check of the answer's design</h2>\n" << check_table(s["verification"]);
  if (!s.value("verified", false)) h << nearest_html(s);
  h << spread_html(s) << "<p>Constraints at the optimum on the search's own "
    << s["optimization"]["samples_per_evaluation"]
    << " samples (95% intervals; binding: within 2% of the limit):</p><ul>\n";
  for (const auto& b : s["constraints_on_search_samples"]) {
    h << "<li>" << str(b, "text") << (b["binding"].get<bool>() ? " <b>(binding)</b>" : "") << "</li>\n";
  }
  h << "</ul>\n";
  return h.str();
}

std::string searches_html(const json& s) {
  std::ostringstream h;
  h << "<h2 id='searches'>Searches</h2>\n<table><tr><th class='l'>choice</th><th class='l'>status</th><th>evaluations"
       "</th><th>feasible</th><th class='l'>design</th><th>objective (search samples)</th></tr>\n";
  for (const auto& r : s["runs"]) {
    h << "<tr><td class='l'>" << str(r, "label") << (r.value("headline", false) ? " (headline)" : "")
      << (r.value("optimization_pick", false) ? " (search's pick)" : "") << "</td><td class='l'>" << str(r, "status")
      << "</td><td>" << r["evaluations"] << "</td><td>" << (r["feasible"].get<bool>() ? "yes" : "no")
      << "</td><td class='l'>" << str(r, "design") << "</td><td>"
      << (r["feasible"].get<bool>() ? number(r["objective"]) : "") << "</td></tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

std::string choice_rows_html(const json& comparison, bool pareto) {
  std::ostringstream h;
  for (const auto& r : comparison["choices"]) {
    h << "<tr><td class='l'>" << str(r, "label") << (r["best"].get<bool>() ? " (headline)" : "")
      << (r.value("selection_pick", false) && !r["best"].get<bool>() ? " (selection set's pick)" : "")
      << (r["optimization_pick"].get<bool>() ? " (search's pick)" : "") << "</td>";
    if (!r.contains("selection")) {
      h << "<td colspan='" << (pareto ? 6 : 5) << "'>no feasible design</td></tr>\n";
      continue;
    }
    if (!r.contains("comparison")) {  // a fast search: not a finalist, so not on the comparison set
      h << "<td>" << number(r["selection"]["objective"]) << "</td><td colspan='" << (pareto ? 5 : 4)
        << "' class='l'>not a finalist: not run on the comparison set</td></tr>\n";
      continue;
    }
    h << "<td>" << number(r["selection"]["objective"]) << "</td><td>" << ci_text(r["objective"]) << "</td>";
    if (pareto) h << "<td>" << (r.contains("second") ? ci_text(r["second"]) : "") << "</td>";
    if (r.contains("minus_best")) {
      const json& d = r["minus_best"];
      json dd{{"value", d["difference"]}};
      if (d.contains("lo")) dd["lo"] = d["lo"];
      if (d.contains("hi")) dd["hi"] = d["hi"];
      h << "<td>" << ci_text(dd) << "</td><td>"
        << (d.contains("bootstrap_share_reference_ahead") ? percent(d["bootstrap_share_reference_ahead"]) : "")
        << "</td>";
    } else {
      h << "<td>(headline)</td><td></td>";
    }
    h << "<td class='l'>" << str(r["comparison"], "verdict") << "</td></tr>\n";
  }
  return h.str();
}

std::string by_parameter_html(const json& comparison, const std::string& margin) {
  std::ostringstream h;
  for (const auto& p : comparison.value("by_parameter", json::array())) {
    h << "<p><b>" << str(p, "parameter") << "</b>: each value's best combination (picked on the selection set) "
      << "against the headline's value, equivalence margin " << html_escape(margin) << ":</p>\n<ul>\n";
    for (const auto& v : p["values"]) {
      h << "<li>" << str(v, "value") << ": ";
      if (!v.contains("run")) {
        h << "no feasible design</li>\n";
        continue;
      }
      h << str(v, "label") << ", " << ci_text(v["objective"]);
      if (v.contains("equivalence")) h << "; " << str(v["equivalence"], "text");
      if (v["headline_value"].get<bool>()) h << " (headline)";
      h << "</li>\n";
    }
    h << "</ul>\n";
  }
  return h.str();
}

std::string choices_html(const json& s) {
  if (!s.contains("choices_compared")) return "";
  const json& o = s["optimization"];
  const bool pareto = s.contains("pareto");
  std::ostringstream h;
  h << "<h2 id='choices'>Choices decided on fresh samples</h2>\n<p>Each combination's best design (from its search) "
       "run on two independent fresh sets of "
    << o["verification_samples"] << " samples: the <i>selection set</i> (seed " << o["selection_seed"]
    << ") picks the best combination and, per value of a choice parameter, its best combination; the <i>comparison "
       "set</i> (seed "
    << o["verification_seed"]
    << ") compares them, so no figure below was used to pick what it describes. A choice is called better only "
       "when its paired difference interval excludes zero; where no difference is shown and the study has a second "
       "objective, the cheaper choice is the headline. Differences are paired (same units), "
       "bootstrap 95% intervals; 'bootstrap share' is the share of bootstrap resamples in which the headline stays "
       "ahead: a resampling share, not a probability that it is better. Constraints are re-checked on the comparison "
       "set."
    << (o.value("search_model", std::string()) == "fast"
            ? " The searches and the selection set ran the kind's fast model; the comparison set runs the full "
              "model, on the finalists: the selection set's pick and each choice value's best combination."
            : "")
    << "</p>\n<table><tr><th class='l'>choice</th><th>selection set</th><th>comparison set [95% CI]</th>"
    << (pareto ? "<th>second objective</th>" : "")
    << "<th>minus headline [95% CI]</th><th>bootstrap share headline ahead</th><th class='l'>constraints</th></tr>\n"
    << choice_rows_html(s["choices_compared"], pareto) << "</table>\n"
    << by_parameter_html(s["choices_compared"], o.value("equivalence_margin", std::string()));
  return h.str();
}

std::string pareto_html(const json& s) {
  if (!s.contains("pareto")) return "";
  const json& p = s["pareto"];
  const std::string second =
      p["second"]["statistic"].get<std::string>() + " " + p["second"]["output"].get<std::string>();
  const std::string objective =
      p["objective"]["statistic"].get<std::string>() + " " + p["objective"]["output"].get<std::string>();
  std::ostringstream h;
  h << "<h2 id='pareto'>Pareto front</h2>\n<p>" << p["evaluations"]
    << " evaluations (the objective, the second objective, and " << p.value("points", 0)
    << " epsilon-constrained searches per choice); the front is the feasible evaluations no other beats on both. Each "
       "front point run on the comparison set (95% intervals)"
    << (s["optimization"].value("search_model", std::string()) == "fast"
            ? ", on the fast model as the searches: the front informs, the headline's check on the full model decides"
            : "")
    << ".</p>\n<table><tr><th class='l'>choice</th>"
       "<th class='l'>design</th><th>"
    << html_escape(second) << "</th><th>" << html_escape(objective)
    << " (search samples)</th><th>fresh samples [95% CI]</th><th class='l'>constraints</th></tr>\n";
  for (const auto& f : p["front"]) {
    h << "<tr><td class='l'>" << str(f, "label") << "</td><td class='l'>" << design_text(f["x"]) << "</td><td>"
      << (f.contains("second") ? ci_text(f["second"]) : "") << "</td><td>" << number(f["objective_optimization"])
      << "</td><td>" << ci_text(f["objective"]) << "</td><td class='l'>" << str(f, "constraints_verdict")
      << "</td></tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

}  // namespace

std::string optimization_report_html(const json& s, const std::filesystem::path& plots_dir,
                                     const std::vector<std::string>& figures) {
  const json& o = s["optimization"];
  const std::string title =
      o.value("title", std::string()).empty() ? o.value("name", std::string()) : o.value("title", std::string());
  std::ostringstream h;
  h << report_page_head(o.value("name", std::string())) << "<h1>" << html_escape(title) << "</h1>\n" << opening_html(s);
  if (s.value("feasible", false)) h << fresh_check_html(s);
  h << searches_html(s) << choices_html(s) << pareto_html(s);
  if (!s.value("feasible", false))
    h << "<h2 id='infeasible'>No feasible design</h2>\n<p>" << str(s, "message") << "</p>\n";
  if (!figures.empty()) h << "<h2 id='figures'>Figures</h2>\n" << figures_html(plots_dir, figures);
  if (!o.value("notes", std::string()).empty()) {
    h << "<h2 id='notes'>Notes of the study file (its author's text, not this run's figures)</h2>\n<pre>"
      << str(o, "notes") << "</pre>\n";
  }
  h << "<p><small>Files beside this page: <a href='summary.json'>summary.json</a>, <a href='history.csv'>history.csv"
       "</a>"
    << (s.contains("pareto") ? ", <a href='pareto.csv'>pareto.csv</a>" : "")
    << ", plots/.</small></p>\n</body></html>\n";
  return with_contents(h.str());
}

}  // namespace poise::engine
