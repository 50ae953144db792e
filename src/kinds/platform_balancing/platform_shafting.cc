#include "kinds/platform_balancing/platform_shafting.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "core/units.h"
#include "engine/kind_interface/study_evaluation.h"
#include "engine/kind_interface/study_kind.h"
#include "kinds/platform_balancing/platform_study_config.h"

namespace poise::kinds::platform_balancing {
using namespace poise::engine;
namespace {

// The SI value of one display unit of the study's output `name`, which must be of dimension
// `dim` (`what` for the message).
double unit_of_output(const StudyConfig& cfg, const StudyConfig& shafting, const std::string& key,
                      const std::string& name, const units::Dimension& dim, const std::string& what) {
  const std::vector<OutputSpec> outputs = study_kind(shafting.kind).outputs(shafting);
  std::string all;
  for (const auto& o : outputs) {
    all += (all.empty() ? "" : ", ") + o.name;
    if (o.name != name) continue;
    const units::Quantity q = unit_quantity(o.unit);
    if (q.dim != dim) {
      throw Error(cfg.file + ": [platform.shafting] " + key + " = \"" + name + "\": the study " + shafting.file +
                  " gives it in " + (o.unit.empty() ? std::string("1") : o.unit) + ", expected " + what);
    }
    return q.value;
  }
  throw Error(cfg.file + ": [platform.shafting] " + key + " = \"" + name + "\": the study " + shafting.file +
              " has no such output (its outputs: " + all + ")");
}

}  // namespace

void check_shafting_study(const StudyConfig& cfg) {
  const PlatformStudySection& ps = platform_sections(cfg).platform;
  if (ps.shafting_study.empty()) return;
  const StudyConfig sc = load_study(ps.shafting_study);
  unit_of_output(cfg, sc, "output", ps.shafting_output, units::kAngle, "an angle");
  unit_of_output(cfg, sc, "pixel_output", ps.shafting_pixel_output, units::kPixel, "px");
}

ShaftingLos compute_shafting_los(const StudyConfig& cfg, int threads) {
  ShaftingLos out;
  const PlatformStudySection& ps = platform_sections(cfg).platform;
  if (ps.shafting_study.empty()) return out;
  const StudyConfig sc = load_study(ps.shafting_study);
  const double angle_si = unit_of_output(cfg, sc, "output", ps.shafting_output, units::kAngle, "an angle");
  unit_of_output(cfg, sc, "pixel_output", ps.shafting_pixel_output, units::kPixel, "px");
  // Through the kind interface (no kind includes another): the study's ok samples.
  const McResult e = evaluate_study(sc, {}, ps.shafting_samples, sc.seed, threads);
  const std::vector<double>& angle = e.values[e.index(ps.shafting_output)];
  const std::vector<double>& px = e.values[e.index(ps.shafting_pixel_output)];
  // A ratio of two units' SI values: exactly 1 for an output in arcsec.
  const double to_arcsec = angle_si / unit_quantity("arcsec").value;
  double lo = INFINITY, hi = 0.0;
  for (std::size_t k = 0; k < angle.size(); ++k) {
    out.los_max_arcsec.push_back(angle[k] * to_arcsec);
    if (px[k] > 0.0) {
      lo = std::min(lo, angle[k] * to_arcsec / px[k]);
      hi = std::max(hi, angle[k] * to_arcsec / px[k]);
    }
  }
  if (!(hi > 0.0) || hi - lo > 1e-9 * hi) {
    throw Error(cfg.file + ": [platform.shafting] " + ps.shafting_output + " and " + ps.shafting_pixel_output + " of " +
                sc.file + " are not one error in two units (their ratio, the pixel's angle, runs from " +
                std::to_string(lo) + " to " + std::to_string(hi) + " arcsec)");
  }
  out.pixel_arcsec = 0.5 * (lo + hi);
  std::sort(out.los_max_arcsec.begin(), out.los_max_arcsec.end());
  return out;
}

}  // namespace poise::kinds::platform_balancing
