#include "cli/balance_design.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "balancing/iso_figures.h"
#include "cli/balance_calibration.h"
#include "core/error.h"
#include "core/format.h"
#include "engine/kind_interface/output_spec.h"
#include "engine/kind_interface/study_kind.h"
#include "engine/study_files/study_config.h"
#include "sampling/statistics.h"

namespace poise::cli {
namespace {

const char* figure_name(const std::string& figure) {
  return figure == "urr" ? "URR" : figure == "umar" ? "U_mar" : "influence coefficient |h|";
}

// The campaign's figure in SI (URR a fraction, U_mar kg m), if it has one.
std::optional<double> iso_figure(const balancing::IsoFigures& iso, const balancing::DesignCompare& k) {
  if (k.figure == "urr") {
    double sum = 0.0;
    std::size_t n = 0;
    for (const auto& f : iso.urr) {
      if (f.plane != k.plane) continue;
      sum += f.urr;
      ++n;
    }
    if (n == 0) return std::nullopt;
    return sum / static_cast<double>(n);
  }
  for (const auto& f : iso.umar) {
    if (f.plane == k.plane) return f.unit == "g mm" ? f.umar * 1e-6 : std::optional<double>();
  }
  return std::nullopt;
}

}  // namespace

units::Dimension figure_dimension(const balancing::BalancingCampaign& c, const std::string& figure) {
  if (figure == "urr") return units::kDimensionless;
  units::Dimension d{{1, 1, 0, 0, 0, 0, 0}};  // an unbalance
  if (figure == "influence") {
    // A reading per unbalance.
    const units::Dimension reading = engine::unit_quantity(c.amplitude_unit).dim;
    for (std::size_t i = 0; i < d.e.size(); ++i) d.e[i] = static_cast<std::int8_t>(reading.e[i] - d.e[i]);
  }
  return d;
}

RealCoefficient real_influence(const balancing::BalancingCampaign& c, const balancing::CampaignAnalysis& a,
                               const balancing::DesignCompare& k) {
  const auto s = static_cast<std::size_t>(std::find(c.sensors.begin(), c.sensors.end(), k.sensor) - c.sensors.begin());
  const auto p = static_cast<std::size_t>(std::find(c.planes.begin(), c.planes.end(), k.plane) - c.planes.begin());
  const double radius = c.plane_radius[p];
  if (radius <= 0.0) {
    throw Error("[[design.compare]] figure = \"influence\" of plane " + k.plane +
                ": its [[plane]] needs a radius (radius = \"50 mm\"): the masses are grams at that radius, the "
                "study's coefficients are per unbalance");
  }
  // h is a reading per gram at the radius: per kg m, times the reading's SI factor.
  const double factor = engine::unit_quantity(c.amplitude_unit).value / (1e-3 * radius);
  const auto& h = a.calibration.h[s][p];
  return {std::abs(h.value) * factor, h.se.value_or(0.0) * factor};
}

std::vector<DesignComparison> compare_with_design(const balancing::BalancingCampaign& c,
                                                  const balancing::CampaignAnalysis& a, const engine::McResult& sim,
                                                  const std::vector<engine::OutputSpec>& outputs) {
  std::vector<DesignComparison> out;
  const balancing::IsoFigures iso = balancing::iso_figures(c, a);
  for (const auto& k : c.design->compare) {
    DesignComparison d{k.figure, k.plane, k.output, "", std::nullopt, 0.0, 0.0, 0.0, 0, false, ""};
    const std::size_t index = sim.index(k.output);
    d.unit = engine::output_unit_of(outputs, k.output);
    const units::Dimension needed = figure_dimension(c, k.figure);
    if (engine::unit_quantity(d.unit).dim != needed) {
      throw Error(fmt::format(
          "[[design.compare]] of {}: the study's output {} is in '{}', expected {}", k.figure, k.output, d.unit,
          k.figure == "urr" ? "a ratio (%, 1)"
          : k.figure == "umar"
              ? "an unbalance (g*mm, kg*m)"
              : "the campaign's reading (" + c.amplitude_unit + ") per unbalance: " + units::dimension_name(needed)));
    }
    std::vector<double> values = sim.values[index];
    d.samples = values.size();
    if (values.empty()) throw Error("the design study " + c.design->study + " gave no sample of " + k.output);
    std::sort(values.begin(), values.end());
    d.p2_5 = sampling::quantile_value_sorted(values.size(), 0.025, [&](std::size_t i) { return values[i]; });
    d.p97_5 = sampling::quantile_value_sorted(values.size(), 0.975, [&](std::size_t i) { return values[i]; });
    const auto si = k.figure == "influence" ? std::optional(real_influence(c, a, k).value) : iso_figure(iso, k);
    const std::string what = k.figure == "influence" ? fmt::format("|h| of plane {} at sensor {}", k.plane, k.sensor)
                                                     : fmt::format("{} of {}", figure_name(k.figure), k.plane);
    if (si) {
      const units::Quantity q = engine::unit_quantity(d.unit);
      d.real = *si / q.value;
      d.share_below = static_cast<double>(std::upper_bound(values.begin(), values.end(), *d.real) - values.begin()) /
                      static_cast<double>(values.size());
      d.within = *d.real >= d.p2_5 && *d.real <= d.p97_5;
      d.sentence = fmt::format(
          "the real {} is {} {}: {} of {} simulated machines are at or below it; {} the design study's central "
          "95% ({} to {} {})",
          what, significant(*d.real, 4), d.unit, significant(100.0 * d.share_below, 3) + "%", d.samples,
          d.within ? "within" : "OUTSIDE", significant(d.p2_5, 4), significant(d.p97_5, 4), d.unit);
    } else {
      d.sentence = fmt::format("the campaign has no {} (check runs{} with a test mass there)", what,
                               k.figure == "umar" ? " marked umar = true" : "");
    }
    out.push_back(d);
  }
  return out;
}

balancing::DesignRunner design_runner(int threads) {
  return [threads](const balancing::BalancingCampaign& c, const balancing::CampaignAnalysis& a) {
    balancing::DesignResult r;
    if (!c.design) return r;
    const engine::StudyConfig cfg = engine::load_study(c.design->study);
    const engine::StudyKind& kind = engine::study_kind(cfg.kind);
    const engine::McResult sim = kind.evaluate(cfg, {}, c.design->samples, cfg.seed, threads);
    const auto outputs = kind.outputs(cfg);
    r.comparisons = compare_with_design(c, a, sim, outputs);
    if (c.design->calibrate) r.calibration = calibrate_design(c, a, cfg, sim, threads);
    return r;
  };
}

}  // namespace poise::cli
