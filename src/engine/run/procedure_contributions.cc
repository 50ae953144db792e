#include "engine/run/procedure_contributions.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "engine/report/report_figures.h"
#include "engine/report/report_plot.h"
#include "engine/results/requirements.h"
#include "engine/results/result_io.h"
#include "engine/study_files/toml_reader.h"

namespace poise::engine {
namespace {
using nlohmann::json;

// "0 <unit>" for a tolerance written "<number> <unit>" at `key` + ".tolerance" (an override
// of the study first, else the model file); nullopt when it is a range or not there.
std::optional<std::string> zero_of(const StudyConfig& cfg, const toml::table& model, const std::string& key) {
  std::string text;
  if (const auto it = cfg.overrides.find(key + ".tolerance"); it != cfg.overrides.end()) {
    text = it->second;
  } else if (const auto* node = model.at_path(key + ".tolerance").as_string()) {
    text = node->get();
  } else if (const auto* number = model.at_path(key + ".tolerance").node(); number && (number->is_number())) {
    return std::string("0");
  } else {
    return std::nullopt;
  }
  const auto space = text.find_first_of(" \t%");
  std::string zero = "0";
  if (space != std::string::npos) zero.append(text, space, std::string::npos);
  return zero;
}

json run_without(const StudyConfig& cfg, const StudyFactory& make_study, const std::map<std::string, std::string>& extra,
                 std::size_t samples, std::uint64_t seed, int threads, const std::vector<OutputSpec>& outputs) {
  StudyConfig c = cfg;
  auto overrides = c.overrides;
  for (const auto& [k, v] : extra) overrides[k] = v;
  c.overrides = apply_study_overrides(c, overrides);
  const McResult mc = make_study(c, samples, seed)->run(threads, false, nullptr, {});
  return {{"samples", mc.completed}, {"failures", mc.failures}, {"outputs", outputs_json(mc, outputs, false)}};
}

}  // namespace

json run_procedure_contributions(const StudyConfig& cfg, const StudyFactory& make_study,
                                 const std::vector<std::string>& tolerance_keys, std::size_t samples, std::uint64_t seed,
                                 int threads, bool progress, const std::vector<OutputSpec>& outputs) {
  json out = json::array();
  const toml::table model = parse_toml_file(cfg.model_path);
  std::vector<std::string> keys;
  for (const auto& k : tolerance_keys) {
    if (!k.empty() && std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
  }
  if (progress) std::fprintf(stderr, "  contributions: %zu runs of %zu samples\n", keys.size() + 1, samples);
  json all = run_without(cfg, make_study, {}, samples, seed, threads, outputs);
  all["without"] = "(nothing: all tolerances)";
  out.push_back(all);
  for (const auto& key : keys) {
    const std::optional<std::string> zero = zero_of(cfg, model, key);
    if (!zero) {
      out.push_back({{"without", key}, {"skipped", "given as a range (min, max) or with no tolerance value: no zero"}});
      continue;
    }
    try {
      json j = run_without(cfg, make_study, {{key + ".tolerance", *zero}}, samples, seed, threads, outputs);
      j["without"] = key;
      out.push_back(j);
    } catch (const ValidationError& e) {
      out.push_back({{"without", key}, {"skipped", std::string("the model refuses it at zero: ") + e.what()}});
    }
  }
  return out;
}

std::string contributions_html(const json& contributions, const json& requirements, const std::vector<OutputSpec>& outputs,
                               const std::filesystem::path& plots_dir, bool plots) {
  if (!contributions.is_array() || contributions.empty() || !contributions[0].contains("outputs")) return "";
  // The statistics shown: those the requirements name, else p95 of the first output.
  const auto shown = shown_statistics(requirements, outputs, 1);
  const json& all = contributions[0];
  std::string h = "<h2>Which tolerance drives the error</h2>\n<p>The study re-run with one tolerance set to zero "
                  "at a time (" + std::to_string(all["samples"].get<std::size_t>()) + " samples each, the same random "
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
    std::sort(bars.begin(), bars.end(), [](const auto& a, const auto& b) { return std::abs(a.second) > std::abs(b.second); });
    std::string why;
    if (plots) {
      tornado_figure(plots_dir, "contributions_" + name + "_" + stat, "Drop of " + stat + " of " + name + " without each tolerance",
                     "drop [" + unit + "]", bars, figures, why);
    }
  }
  return h + figures_html(plots_dir, figures);
}

}  // namespace poise::engine
