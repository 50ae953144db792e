#include "engine/kind_interface/study_evaluation.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"
#include "engine/kind_interface/study_kind.h"
#include "sampling/statistics.h"

namespace poise::engine {

namespace {

std::map<std::string, std::string> merged(const StudyConfig& cfg, const std::map<std::string, std::string>& extra) {
  auto o = cfg.overrides;
  for (const auto& [k, v] : extra) o[k] = v;
  return o;
}

}  // namespace

McResult evaluate_study(const StudyConfig& base, const std::map<std::string, std::string>& overrides,
                        std::size_t samples, std::uint64_t seed, int threads) {
  StudyConfig cfg = base;
  const StudyKind& kind = study_kind(cfg.kind);
  const auto model_overrides = kind.apply_study_overrides(cfg, merged(base, overrides));
  McResult e = kind.evaluate(cfg, model_overrides, samples, seed, threads);
  e.replicate_size = cfg.replicate_size;  // the design's replicates, for intervals that cover
  return e;
}

std::vector<std::string> study_output_names(const StudyConfig& base) {
  StudyConfig cfg = base;
  const StudyKind& kind = study_kind(cfg.kind);
  cfg.overrides = kind.apply_study_overrides(cfg, base.overrides);
  std::vector<std::string> names;
  for (const auto& o : kind.outputs(cfg)) names.push_back(o.name);
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
  if (name.rfind("fraction_within:", 0) == 0) {
    // The share of values within [lo, hi] (a NaN, a failed sample's, is not within).
    const std::size_t colon = name.find(':', 16);
    if (colon == std::string::npos) throw Error("unknown statistic '" + name + "'");
    const double lo = std::stod(name.substr(16, colon - 16)), hi = number_after(colon + 1);
    double k = 0.0;
    for (double y : v) k += (y >= lo && y <= hi) ? 1.0 : 0.0;
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
    // The quantile definition of summary.json (sampling/statistics.h: Hyndman & Fan 8,
    // median-unbiased), so that an objective and its reported figure agree.
    return sampling::quantile_value(v, p / 100.0);
  }
  throw Error("unknown statistic '" + name +
              "'; use mean, std, min, max, p<q> (p50, p95, p99.73), fraction_le:<x>, fraction_ge:<x> or "
              "fraction_within:<lo>:<hi>");
}

}  // namespace poise::engine
