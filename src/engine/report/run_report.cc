#include "engine/report/run_report.h"

#include "engine/run/stack_up.h"

#include <optional>

#include <algorithm>
#include <sstream>

#include "core/number_text.h"
#include "engine/report/driver_scatter.h"
#include "engine/report/report_contents.h"
#include "engine/report/report_figures.h"
#include "engine/report/report_plot.h"
#include "engine/report/result_sections.h"
#include "engine/results/references.h"
#include "engine/results/result_io.h"
#include "sampling/distribution.h"

namespace poise::engine {
using nlohmann::json;

namespace {

// The distribution figures of the main outputs (those a reference or requirement names
// first), with the references and requirement limits as lines; returns a note when gnuplot
// could not make one.
std::string distribution_plots(const json& s, const FinishedRun& f, const std::filesystem::path& pdir,
                               std::vector<std::string>& figures) {
  const auto& names = f.study.output_names();
  json named = s["requirements"];
  for (const auto& r : s["references"]) named.push_back(r);
  std::string note;
  for (const auto& name : main_outputs(names, named)) {
    const auto k = static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
    if (k >= f.mc.values.size()) continue;
    std::vector<FigureLine> lines;
    for (const auto& r : s["requirements"]) {
      if (r["output"] == name) {
        lines.push_back({r["limit"]["value"].get<double>(),
                         "requirement: " + r["statistic"].get<std::string>() +
                             (r["at_most"].get<bool>() ? " <= " : " >= ") + r["limit"]["as_written"].get<std::string>(),
                         "#cc3311"});
      }
    }
    for (const auto& c : s["references"]) {
      if (c["output"] == name)
        lines.push_back({c["reference"].get<double>(), c["name"].get<std::string>(),
                         c["role"] == "validation" ? "#228833" : "#999999"});
    }
    std::string why;
    if (!distribution_figures(pdir, name, f.study.outputs()[k].unit, f.study.outputs()[k].description, f.mc.values[k],
                              f.mc.ok_index, lines, figures, why)) {
      note = why;
    }
    if (s.contains("sensitivity") && !sensitivity_tornado(pdir, s["sensitivity"], name, figures, why)) note = why;
  }
  // The first main output against the inputs that drive it most (from samples.csv's first rows).
  const auto shown = main_outputs(names, named);
  if (!shown.empty()) {
    const auto k = static_cast<std::size_t>(std::find(names.begin(), names.end(), shown.front()) - names.begin());
    std::string why;
    if (k < f.study.outputs().size() && !driver_scatter(pdir, pdir.parent_path() / "samples.csv", f.study.input_names(),
                                                        f.study.outputs()[k], figures, why)) {
      note = why;
    }
  }
  return note;
}

// A statistic with its interval, at the decimal place the interval supports (core/number_text.h).
std::string statistic_cell(const json& e) {
  auto end = [&](int k) {
    return e["ci95"][k].is_number() ? std::optional<double>(e["ci95"][k].get<double>()) : std::nullopt;
  };
  const IntervalText t = interval_text(e["value"].get<double>(), end(0), end(1));
  return t.value + " <small>[" + (t.lo.empty() ? std::string("&ndash;") : t.lo) + ", " +
         (t.hi.empty() ? std::string("&ndash;") : t.hi) + "]</small>";
}

// report.html: the answer first, then what was run, the study's own sections, the outputs,
// sweeps, convergence, figures, notes and provenance.
}  // namespace

std::string run_report_html(const json& s, const FinishedRun& f, const std::filesystem::path& pdir, bool plots) {
  const StudyConfig& cfg = f.cfg;
  std::vector<std::string> figures;
  const std::string plot_note = plots && !f.mc.outputs.empty() ? distribution_plots(s, f, pdir, figures) : "";
  std::ostringstream h;
  h << report_page_head(cfg.name) << "<h1>" << html_escape(cfg.title.empty() ? cfg.name : cfg.title) << "</h1>\n"
    << answer_html(s["answer"].get<std::string>(), s["requirements"]) << "<p>Study <code>" << html_escape(cfg.file)
    << "</code>, model <code>" << html_escape(cfg.model_path) << "</code> (" << html_escape(f.study.model_source())
    << "). " << f.ran << " simulated samples (" << sampling::to_string(cfg.method) << ", seed " << f.plan.seed << "), "
    << f.mc.failures << " failed.</p>\n";
  if (f.status != "complete") {
    h << "<p><b>This run is " << f.status
      << "</b>: " << html_escape(f.mc.stop_reason.empty() ? "stopped by a signal" : f.mc.stop_reason)
      << ". The figures below cover the " << f.ran << " samples that ran.</p>\n";
  }
  if (s.contains("sensitivity")) h << sensitivity_html(s["sensitivity"]);
  h << references_html(s["references"]);
  f.study.report_sections(f.mc, pdir.string(), plots, figures, h);
  h << "<h2>Outputs per sample</h2>\n<table><tr><th class='l'>output</th><th>mean</th><th>std</th><th>min</th>"
       "<th>p0.135</th><th>p50</th><th>p95</th><th>p99.73</th><th>max</th></tr>\n";
  for (const auto& [name, o] : s["outputs"].items()) {
    h << "<tr><td class='l'><code>" << html_escape(name) << "</code> " << html_escape(o["unit"].get<std::string>());
    if (o.contains("description")) h << "<br><small>" << html_escape(o["description"].get<std::string>()) << "</small>";
    h << "</td>";
    for (const char* statistic : {"mean", "std", "min", "p0_135", "p50", "p95", "p99_73", "max"}) {
      h << "<td>" << statistic_cell(o[statistic]) << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</table>\n";
  if (s.contains("stack_up")) h << stack_up_html(s["stack_up"]);
  if (s.contains("sweeps")) h << sweeps_html(s["sweeps"], f.study.outputs(), pdir, plots);
  if (s.contains("contributions")) {
    h << contributions_html(s["contributions"], s["requirements"], f.study.outputs(), pdir, plots);
  }
  h << convergence_html(s["sample_convergence"]) << "<h2>Figures</h2>\n";
  if (!plot_note.empty()) h << "<p>" << html_escape(plot_note) << "</p>\n";
  h << figures_html(pdir, figures);
  if (!cfg.notes.empty()) h << "<h2>Notes of the study</h2>\n<pre>" << html_escape(cfg.notes) << "</pre>\n";
  h << provenance_html(s["provenance"]);
  if (s.contains("solver")) h << "<h3>Solver</h3>\n<pre>" << html_escape(s["solver"].dump(2)) << "</pre>\n";
  // Links to the files the run wrote ([output] keys may leave samples.csv and samples.h5 out).
  h << "<p><small>Files beside this page: <a href='summary.json'>summary.json</a>, ";
  for (const char* file : {"samples.csv", "samples.h5"}) {
    if (std::filesystem::exists(pdir.parent_path() / file)) h << "<a href='" << file << "'>" << file << "</a>, ";
  }
  h << "<a href='run.json'>run.json</a>, <a href='plots/'>plots/</a> (each figure's data and gnuplot "
       "script).</small></p>\n"
       "</body></html>\n";
  return with_contents(h.str());
}

}  // namespace poise::engine
