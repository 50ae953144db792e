#include "engine/sensitivity_output.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <span>

#include "core/error.h"
#include "sampling/sensitivity.h"
#include "engine/result_io.h"

namespace poise::studies {
using nlohmann::json;

json sensitivity_json(const std::vector<std::string>& outputs, const std::vector<std::string>& groups, std::size_t base,
                      const std::vector<std::vector<double>>& values, std::uint64_t seed) {
  const std::size_t k = groups.size();
  json out{{"base_rows", base},
           {"groups", groups},
           {"evaluations", base * (k + 2)},
           {"method", "Saltelli 2010 radial layout; first order S (Saltelli 2010), total ST (Jansen 1999); 95% "
                      "percentile bootstrap over base rows (1000 resamples)"},
           {"reading", "S: share of the output's variance due to the input alone; ST: share including its "
                       "interactions; ST - S large means interactions; sum of S < 1 means interactions too"},
           {"outputs", json::object()}};
  for (std::size_t o = 0; o < outputs.size() && o < values.size(); ++o) {
    const std::vector<double>& v = values[o];
    require(v.size() >= base * (k + 2), "sensitivity: fewer samples than the layout needs");
    const std::span<const double> all(v);
    std::vector<std::span<const double>> ab;
    for (std::size_t g = 0; g < k; ++g) ab.push_back(all.subspan((2 + g) * base, base));
    const sampling::SobolResult r = sampling::sobol_indices(all.subspan(0, base), all.subspan(base, base), ab, seed);
    json idx = json::array();
    for (std::size_t g = 0; g < k; ++g) {
      idx.push_back({{"group", groups[g]}, {"first", estimate_json(r.groups[g].first)},
                     {"total", estimate_json(r.groups[g].total)}, {"rows_used", r.groups[g].rows_used}});
    }
    std::stable_sort(idx.begin(), idx.end(), [](const json& a, const json& b) {
      const double ta = a["total"]["value"].is_number() ? a["total"]["value"].get<double>() : -1.0;
      const double tb = b["total"]["value"].is_number() ? b["total"]["value"].get<double>() : -1.0;
      return ta > tb;
    });
    out["outputs"][outputs[o]] = {{"variance", r.variance}, {"rows", r.n}, {"first_sum", estimate_json(r.first_sum)},
                                  {"indices", idx}, {"note", r.note}};
  }
  return out;
}

std::string sensitivity_html(const json& s) {
  auto f = [](const json& e) {
    if (!e["value"].is_number()) return std::string("&ndash;");
    char buf[120];
    const auto end = [](const json& x) { return x.is_number() ? x.get<double>() : NAN; };
    std::snprintf(buf, sizeof buf, "%.3f <small>[%.3f, %.3f]</small>", e["value"].get<double>(), end(e["ci95"][0]),
                  end(e["ci95"][1]));
    return std::string(buf);
  };
  std::string h = "<h2>Which input drives each output (Sobol indices)</h2>\n<p>" +
                  html_escape(s["method"].get<std::string>()) + "; " + std::to_string(s["base_rows"].get<std::size_t>()) +
                  " base rows, " + std::to_string(s["evaluations"].get<std::size_t>()) + " evaluations. " +
                  html_escape(s["reading"].get<std::string>()) + ". Groups whose total index is below 0.01 at both ends are left out.</p>\n";
  for (const auto& [name, o] : s["outputs"].items()) {
    h += "<h3><code>" + html_escape(name) + "</code></h3>\n";
    if (!o["note"].get<std::string>().empty()) h += "<p>" + html_escape(o["note"].get<std::string>()) + "</p>\n";
    h += "<table><tr><th class='l'>input</th><th>first order S</th><th>total ST</th></tr>\n";
    for (const auto& g : o["indices"]) {
      const json& hi = g["total"]["ci95"][1];
      if (hi.is_number() && hi.get<double>() < 0.01) continue;
      h += "<tr><td class='l'>" + html_escape(g["group"].get<std::string>()) + "</td><td>" + f(g["first"]) + "</td><td>" +
           f(g["total"]) + "</td></tr>\n";
    }
    h += "<tr><td class='l'><i>sum of first order</i></td><td>" + f(o["first_sum"]) + "</td><td></td></tr>\n</table>\n";
  }
  return h;
}

}  // namespace poise::studies
