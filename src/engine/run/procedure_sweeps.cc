#include "engine/run/procedure_sweeps.h"
#include "core/diagnostics.h"

#include <cmath>
#include <cstdio>

#include "core/units.h"
#include "engine/report/report_figures.h"
#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"

namespace poise::engine {
namespace {
using nlohmann::json;

}  // namespace

json run_procedure_sweeps(const StudyConfig& cfg, const StudyFactory& make_study, std::size_t run_samples,
                          std::uint64_t seed, int threads, bool progress, const std::vector<Requirement>& requirements,
                          const std::vector<OutputSpec>& outputs) {
  json sweeps = json::array();
  for (const auto& sw : cfg.sweeps) {
    const std::size_t n = sweep_samples(sw, run_samples);
    json js{{"parameter", sw.parameter}, {"samples", n}, {"points", json::array()}};
    for (const auto& v : sw.values) {
      if (progress)
        diagnostics::progress("  sweep " + sw.parameter + " = " + v + ": " + std::to_string(n) + " samples");
      StudyConfig c = cfg;
      auto overrides = c.overrides;
      overrides[sw.parameter] = v;
      c.overrides = apply_study_overrides(c, overrides);
      const std::unique_ptr<ProcedureStudy> study = make_study(c, n, seed);
      const McResult mc = study->run(threads, false, nullptr, {});
      json p{{"value", v},
             {"value_si", units::parse_quantity(v).value},
             {"samples", mc.completed},
             {"failures", mc.failures}};
      p["outputs"] = outputs_json(mc, outputs, false);
      p["requirements"] = judge_requirements(requirements, outputs, requirement_values(mc, outputs, cfg));
      js["points"].push_back(p);
    }
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
