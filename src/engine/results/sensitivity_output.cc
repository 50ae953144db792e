#include "engine/results/sensitivity_output.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <span>

#include "core/error.h"
#include "engine/results/result_io.h"
#include "sampling/sensitivity.h"

namespace poise::engine {
using nlohmann::json;

std::vector<std::vector<std::size_t>> ToleranceGroups::closed_groups() const {
  std::vector<std::vector<std::size_t>> out;
  for (const auto& d : dims) {
    if (d.size() > 1) out.push_back(d);
  }
  return out;
}

ToleranceGroups tolerance_groups(const std::vector<std::string>& dimension_names,
                                 const std::vector<std::string>& tolerance_of) {
  POISE_INVARIANT(dimension_names.size() == tolerance_of.size(), "one tolerance key per design dimension");
  ToleranceGroups t;
  for (std::size_t d = 0; d < dimension_names.size(); ++d) {
    const std::string& key = tolerance_of[d].empty() ? dimension_names[d] : tolerance_of[d];
    const auto it = std::find(t.names.begin(), t.names.end(), key);
    if (it == t.names.end()) {
      t.names.push_back(key);
      t.dims.push_back({d});
    } else {
      t.dims[static_cast<std::size_t>(it - t.names.begin())].push_back(d);
    }
  }
  return t;
}

namespace {
double total_of(const json& a) { return a["total"]["value"].is_number() ? a["total"]["value"].get<double>() : -1.0; }
void sort_by_total(json& idx) {
  std::stable_sort(idx.begin(), idx.end(), [](const json& a, const json& b) { return total_of(a) > total_of(b); });
}
}  // namespace

json sensitivity_json(const std::vector<std::string>& outputs, const std::vector<std::string>& groups, std::size_t base,
                      const std::vector<std::vector<double>>& values, std::uint64_t seed,
                      const ToleranceGroups& tolerances) {
  const std::size_t k = groups.size();
  const std::vector<std::vector<std::size_t>> closed = tolerances.closed_groups();
  const std::size_t k_all = k + closed.size();
  json out{{"base_rows", base},
           {"groups", groups},
           {"evaluations", base * (k_all + 2)},
           {"method",
            "Saltelli 2010 radial layout; first order S (Saltelli 2010), total ST (Jansen 1999); 95% "
            "percentile bootstrap over base rows (1000 resamples)"},
           {"reading",
            "S: share of the output's variance due to the input alone; ST: share including its "
            "interactions; ST - S large means interactions; sum of S < 1 means interactions too"},
           {"outputs", json::object()}};
  for (std::size_t o = 0; o < outputs.size() && o < values.size(); ++o) {
    const std::vector<double>& v = values[o];
    POISE_INVARIANT(v.size() >= base * (k_all + 2), "sensitivity: fewer samples than the layout needs");
    const std::span<const double> all(v);
    std::vector<std::span<const double>> ab;
    for (std::size_t g = 0; g < k; ++g) ab.push_back(all.subspan((2 + g) * base, base));
    const sampling::SobolResult r = sampling::sobol_indices(all.subspan(0, base), all.subspan(base, base), ab, seed);
    auto entry = [](const std::string& name, const sampling::SobolIndex& x) {
      return json{{"group", name},
                  {"first", estimate_json(x.first)},
                  {"total", estimate_json(x.total)},
                  {"rows_used", x.rows_used}};
    };
    json idx = json::array();
    for (std::size_t g = 0; g < k; ++g) idx.push_back(entry(groups[g], r.groups[g]));
    sort_by_total(idx);
    out["outputs"][outputs[o]] = {{"variance", r.variance},
                                  {"rows", r.n},
                                  {"first_sum", estimate_json(r.first_sum)},
                                  {"indices", idx},
                                  {"note", r.note}};
    if (tolerances.names.empty()) continue;
    // Per tolerance: the closed group of its columns (their AB rows), or its one column's; a
    // group that is no design dimension (the within-sample randomness) stays a source of its own.
    std::vector<std::span<const double>> ab_tol;
    std::vector<std::string> names;
    std::vector<std::size_t> columns;
    std::size_t next_closed = 0;
    for (std::size_t t = 0; t < tolerances.names.size(); ++t) {
      const auto& d = tolerances.dims[t];
      const std::size_t g = d.size() > 1 ? k + next_closed++ : d[0];
      ab_tol.push_back(all.subspan((2 + g) * base, base));
      names.push_back(tolerances.names[t]);
      columns.push_back(d.size());
    }
    for (std::size_t g = 0; g < k; ++g) {
      bool in_dims = false;
      for (const auto& d : tolerances.dims) in_dims = in_dims || std::find(d.begin(), d.end(), g) != d.end();
      if (!in_dims) {
        ab_tol.push_back(all.subspan((2 + g) * base, base));
        names.push_back(groups[g]);
        columns.push_back(0);
      }
    }
    const sampling::SobolResult rt =
        sampling::sobol_indices(all.subspan(0, base), all.subspan(base, base), ab_tol, seed);
    json tol = json::array();
    for (std::size_t t = 0; t < names.size(); ++t) {
      tol.push_back(entry(names[t], rt.groups[t]));
      tol.back()["columns"] = columns[t];
    }
    sort_by_total(tol);
    out["outputs"][outputs[o]]["tolerances"] = tol;
    out["outputs"][outputs[o]]["tolerance_first_sum"] = estimate_json(rt.first_sum);
  }
  return out;
}

}  // namespace poise::engine
