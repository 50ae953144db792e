#include "cli/balance_design.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "balancing/iso_figures.h"
#include "core/error.h"
#include "core/format.h"
#include "engine/kind_interface/output_spec.h"
#include "engine/kind_interface/study_kind.h"
#include "engine/study_files/study_config.h"
#include "sampling/statistics.h"

namespace poise::cli {
namespace {

// The campaign's figure in SI (URR a fraction, U_mar kg m), if it has one.
std::optional<double> real_figure(const balancing::BalancingCampaign& c, const balancing::IsoFigures& iso,
                                  const balancing::DesignCompare& k) {
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
  (void)c;
  return std::nullopt;
}

}  // namespace

std::vector<DesignComparison> compare_with_design(const balancing::BalancingCampaign& c,
                                                  const balancing::CampaignAnalysis& a, int threads) {
  std::vector<DesignComparison> out;
  if (!c.design) return out;
  const engine::StudyConfig cfg = engine::load_study(c.design->study);
  const engine::StudyKind& kind = engine::study_kind(cfg.kind);
  const engine::McResult sim = kind.evaluate(cfg, {}, c.design->samples, cfg.seed, threads);
  const auto outputs = kind.outputs(cfg);
  const balancing::IsoFigures iso = balancing::iso_figures(c, a);
  for (const auto& k : c.design->compare) {
    DesignComparison d{k.figure, k.plane, k.output, "", std::nullopt, 0.0, 0.0, 0.0, 0, false, ""};
    const std::size_t index = sim.index(k.output);
    for (const auto& o : outputs) {
      if (o.name == k.output) d.unit = o.unit;
    }
    const units::Dimension needed = k.figure == "urr" ? units::kDimensionless : units::Dimension{{1, 1, 0, 0, 0, 0, 0}};
    if (engine::unit_quantity(d.unit).dim != needed) {
      throw Error("[[design.compare]] of " + k.figure + ": the study's output " + k.output + " is in '" + d.unit +
                  "', expected " + (k.figure == "urr" ? "a ratio (%, 1)" : "an unbalance (g*mm, kg*m)"));
    }
    std::vector<double> values = sim.values[index];
    d.samples = values.size();
    if (values.empty()) throw Error("the design study " + c.design->study + " gave no sample of " + k.output);
    std::sort(values.begin(), values.end());
    d.p2_5 = sampling::quantile_value_sorted(values.size(), 0.025, [&](std::size_t i) { return values[i]; });
    d.p97_5 = sampling::quantile_value_sorted(values.size(), 0.975, [&](std::size_t i) { return values[i]; });
    const auto si = real_figure(c, iso, k);
    if (si) {
      const units::Quantity q = engine::unit_quantity(d.unit);
      d.real = *si / q.value;
      d.share_below = static_cast<double>(std::upper_bound(values.begin(), values.end(), *d.real) - values.begin()) /
                      static_cast<double>(values.size());
      d.within = *d.real >= d.p2_5 && *d.real <= d.p97_5;
      d.sentence = fmt::format(
          "the real {} of {} is {} {}: {} of {} simulated machines are at or below it; {} the design study's central "
          "95% ({} to {} {})",
          k.figure == "urr" ? "URR" : "U_mar", k.plane, significant(*d.real, 4), d.unit,
          significant(100.0 * d.share_below, 3) + "%", d.samples, d.within ? "within" : "OUTSIDE",
          significant(d.p2_5, 4), significant(d.p97_5, 4), d.unit);
    } else {
      d.sentence = fmt::format("the campaign has no {} of {} (check runs{} with a test mass there)", k.figure, k.plane,
                               k.figure == "umar" ? " marked umar = true" : "");
    }
    out.push_back(d);
  }
  return out;
}

balancing::DesignRunner design_runner(int threads) {
  return [threads](const balancing::BalancingCampaign& c, const balancing::CampaignAnalysis& a) {
    return compare_with_design(c, a, threads);
  };
}

}  // namespace poise::cli
