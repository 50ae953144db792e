#include "studies/study_evaluation.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"
#include "studies/balancing_study.h"
#include "studies/gimbal_study.h"
#include "studies/seeker_los_study.h"
#include "studies/seeker_model.h"
#include "studies/seeker_clearance.h"

namespace poise::studies {

std::size_t StudyEvaluation::index(const std::string& output) const {
  const auto it = std::find(names.begin(), names.end(), output);
  if (it != names.end()) return static_cast<std::size_t>(it - names.begin());
  std::string all;
  for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
  throw Error("no output '" + output + "' in this study; its outputs are: " + all);
}

namespace {

std::map<std::string, std::string> merged(const StudyConfig& cfg, const std::map<std::string, std::string>& extra) {
  auto o = cfg.overrides;
  for (const auto& [k, v] : extra) o[k] = v;
  return o;
}

StudyEvaluation from_procedure(const ProcedureStudy& study, int threads) {
  const McResult mc = study.run(threads, false, nullptr, {});
  StudyEvaluation e;
  e.names = study.output_names();
  e.values = mc.values;
  e.values.resize(e.names.size());
  e.ok_index = mc.ok_index;
  e.samples = mc.n;
  e.failures = mc.failures;
  if (!mc.failed.empty()) e.first_failure = mc.failed.front().second;
  e.wall_seconds = mc.wall_seconds;
  return e;
}

}  // namespace

StudyEvaluation evaluate_study(const StudyConfig& base, const std::map<std::string, std::string>& overrides,
                               std::size_t samples, std::uint64_t seed, int threads) {
  StudyConfig cfg = base;
  const auto o = apply_study_overrides(cfg, merged(base, overrides));
  if (cfg.kind == "balancing_machine") {
    auto e = from_procedure(BalancingStudy(cfg, load_balancing_model(cfg.model_path, o), samples, seed), threads);
    e.replicate_size = cfg.replicate_size;
    return e;
  }
  if (cfg.kind == "gimbal_static_unbalance") {
    auto e = from_procedure(GimbalStudy(cfg, load_gimbal_model(cfg.model_path, o), samples, seed), threads);
    e.replicate_size = cfg.replicate_size;
    return e;
  }
  const SeekerLosStudy study(cfg, load_seeker_model(cfg.model_path, o), samples, seed);
  StudyEvaluation e;
  e.replicate_size = cfg.replicate_size;
  for (const auto& d : kSeekerOutputs) e.names.emplace_back(d.name);
  e.values.resize(e.names.size());
  const SeekerMcResult mc = study.run(threads, false, [&](std::span<const SeekerSampleResult> block) {
    for (const auto& s : block) {
      if (!s.ok) {
        if (e.first_failure.empty()) e.first_failure = s.message;
        continue;
      }
      for (std::size_t k = 0; k < e.names.size(); ++k) e.values[k].push_back(s.outputs[k]);
      e.ok_index.push_back(s.index);
    }
  });
  e.samples = mc.n;
  e.failures = mc.failures;
  e.wall_seconds = mc.wall_seconds;
  if (cfg.geometry.clearance_output) {  // a design constraint: the same for every sample
    const double c = nominal_min_clearance(study.model(), cfg.geometry.clearance_yaw_points,
                                           cfg.geometry.clearance_pitch_points);
    e.names.emplace_back("min_clearance_mm");
    e.values.emplace_back(e.values.empty() ? 0 : e.values[0].size(), 1e3 * c);
  }
  return e;
}

std::vector<std::string> study_output_names(const StudyConfig& base) {
  StudyConfig cfg = base;
  cfg.overrides = apply_study_overrides(cfg, base.overrides);
  if (cfg.kind == "balancing_machine") {
    return BalancingStudy(cfg, load_balancing_model(cfg.model_path, cfg.overrides), 1, cfg.seed).output_names();
  }
  if (cfg.kind == "gimbal_static_unbalance") {
    return GimbalStudy(cfg, load_gimbal_model(cfg.model_path, cfg.overrides), 1, cfg.seed).output_names();
  }
  const SeekerModel model = load_seeker_model(cfg.model_path, cfg.overrides);
  std::vector<std::string> names;
  for (const auto& d : kSeekerOutputs) names.emplace_back(d.name);
  if (cfg.geometry.clearance_output) {
    if (!model.geometry) {
      throw ValidationError({InputError(SourceLocation{cfg.file, 0, 0}, "clearance.output", "true",
                                        "a seeker model with a [geometry] section (" + cfg.model_path + " has none)")});
    }
    names.emplace_back("min_clearance_mm");
  }
  return names;
}

bool is_statistic(const std::string& name) {
  try {
    statistic({1.0, 2.0}, name);
    return true;
  } catch (const Error&) {
    return false;
  }
}

double statistic(std::vector<double> v, const std::string& name) {
  if (v.empty()) throw Error("statistic '" + name + "' of no values (every sample failed?)");
  const double n = static_cast<double>(v.size());
  if (name == "mean") return std::accumulate(v.begin(), v.end(), 0.0) / n;
  if (name == "std") {
    const double m = std::accumulate(v.begin(), v.end(), 0.0) / n;
    double s = 0.0;
    for (double x : v) s += (x - m) * (x - m);
    return v.size() > 1 ? std::sqrt(s / (n - 1.0)) : 0.0;
  }
  if (name == "min") return *std::min_element(v.begin(), v.end());
  if (name == "max") return *std::max_element(v.begin(), v.end());
  auto number_after = [&](std::size_t pos) {
    std::size_t used = 0;
    double x = NAN;
    try {
      x = std::stod(name.substr(pos), &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || pos + used != name.size() || !std::isfinite(x)) {
      throw Error("unknown statistic '" + name + "'");
    }
    return x;
  };
  if (name.rfind("fraction_le:", 0) == 0 || name.rfind("fraction_ge:", 0) == 0) {
    const double x = number_after(12);
    const bool le = name[9] == 'l';
    double k = 0.0;
    for (double y : v) k += (le ? y <= x : y >= x) ? 1.0 : 0.0;
    return k / n;
  }
  if (name.size() > 1 && name[0] == 'p') {
    std::string q = name.substr(1);
    std::replace(q.begin(), q.end(), '_', '.');  // p99_73 as in summary.json
    double p = NAN;
    std::size_t used = 0;
    try {
      p = std::stod(q, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != q.size() || !(p >= 0.0 && p <= 100.0)) throw Error("unknown statistic '" + name + "'");
    // Linear interpolation between order statistics (type 7).
    const double h = (n - 1.0) * p / 100.0;
    const auto lo = static_cast<std::size_t>(std::floor(h));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(lo), v.end());
    const double a = v[lo];
    if (lo + 1 >= v.size()) return a;
    const double b = *std::min_element(v.begin() + static_cast<std::ptrdiff_t>(lo) + 1, v.end());
    return a + (h - static_cast<double>(lo)) * (b - a);
  }
  throw Error("unknown statistic '" + name +
              "'; use mean, std, min, max, p<q> (p50, p95, p99.73), fraction_le:<x> or fraction_ge:<x>");
}

}  // namespace poise::studies
