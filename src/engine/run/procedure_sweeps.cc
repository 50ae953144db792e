#include "engine/run/procedure_sweeps.h"
#include "core/diagnostics.h"

#include <cmath>
#include <cstdio>

#include "core/units.h"
#include "engine/report/report_figures.h"
#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"
#include "engine/run/runs_over_ranks.h"
#include "sampling/distributed.h"

namespace poise::engine {
using nlohmann::json;

json run_procedure_sweeps(const StudyConfig& cfg, const StudyFactory& make_study, std::size_t run_samples,
                          std::uint64_t seed, int threads, bool progress, const std::vector<Requirement>& requirements,
                          const std::vector<OutputSpec>& outputs) {
  // Every (sweep, value) is a run of its own: spread over the MPI ranks, if any.
  std::vector<std::pair<const SweepSpec*, const std::string*>> points;
  for (const auto& sw : cfg.sweeps) {
    for (const auto& v : sw.values) points.emplace_back(&sw, &v);
  }
  const int ranks = sampling::Cluster::size();
  if (progress && ranks > 1) {
    diagnostics::progress("  sweeps: " + std::to_string(points.size()) + " runs over " + std::to_string(ranks) +
                          " MPI ranks");
  }
  const std::vector<json> results = runs_over_ranks(points.size(), [&](std::size_t i) {
    const SweepSpec& sw = *points[i].first;
    const std::string& v = *points[i].second;
    const std::size_t n = sweep_samples(sw, run_samples);
    if (progress && ranks == 1) {
      diagnostics::progress("  sweep " + sw.parameter + " = " + v + ": " + std::to_string(n) + " samples");
    }
    StudyConfig c = cfg;
    auto overrides = c.overrides;
    overrides[sw.parameter] = v;
    c.overrides = apply_study_overrides(c, overrides);
    const std::unique_ptr<ProcedureStudy> study = make_study(c, n, seed);
    const McResult mc = study->run(threads, false, {}, {});
    json p{{"value", v},
           {"value_si", units::parse_quantity(v).value},
           {"samples", mc.completed},
           {"failures", mc.failures}};
    p["outputs"] = outputs_json(mc, outputs, false);
    p["requirements"] = judge_requirements(requirements, outputs, requirement_values(mc, outputs, cfg));
    return p;
  });
  if (!sampling::Cluster::root()) return nullptr;
  json sweeps = json::array();
  std::size_t next = 0;
  for (const auto& sw : cfg.sweeps) {
    json js{{"parameter", sw.parameter}, {"samples", sweep_samples(sw, run_samples)}, {"points", json::array()}};
    for (std::size_t k = 0; k < sw.values.size(); ++k) js["points"].push_back(results[next++]);
    sweeps.push_back(js);
  }
  return sweeps;
}

// The number and unit of a value as written ("70 mm" -> 70, "mm"): sweep axes in the
// user's own unit, not SI.
std::pair<double, std::string> as_written(const std::string& text) {
  std::size_t used = 0;
  double x = NAN;
  try {
    x = std::stod(text, &used);
  } catch (const std::exception&) {
    return {NAN, ""};
  }
  std::string unit = text.substr(used);
  unit.erase(0, unit.find_first_not_of(' '));
  return {x, unit};
}

}  // namespace poise::engine
