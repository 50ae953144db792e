// What the modes of poise_nightly_compare share: JSON files, statistics over repetitions,
// number formatting, the default targets (nightly_common.h).
#include "nightly_common.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>

namespace poise::nightly {

json read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot open " + path);
  try {
    return json::parse(in);
  } catch (const json::parse_error& e) {
    throw InputError(path + ": not valid JSON: " + e.what());
  }
}

void write_json(const std::string& path, const json& j) {
  std::ofstream out(path);
  if (!out) throw InputError("cannot write " + path);
  out << j.dump(2) << '\n';
  if (!out) throw InputError("error writing " + path);
}

double parse_double(const std::string& s, const std::string& what) {
  try {
    std::size_t pos = 0;
    const double v = std::stod(s, &pos);
    if (pos != s.size() || !std::isfinite(v)) throw std::invalid_argument(s);
    return v;
  } catch (const std::exception&) {
    throw InputError(what + ": not a number: '" + s + "'");
  }
}

// Student-t 97.5 % quantile over the normal one, for n - 1 degrees of freedom.
double t_factor(std::size_t n) {
  static constexpr std::array<double, 11> t{0, 12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228};
  const std::size_t dof = n > 0 ? n - 1 : 0;
  if (dof == 0) return 1.0;
  const double q = dof < t.size() ? t[dof] : dof < 20 ? 2.131 : dof < 30 ? 2.086 : 2.042;
  return q / 1.96;
}

Spread spread_of(std::vector<double> v) {
  Spread s;
  s.n = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.min = v.front(), s.max = v.back();
  s.median = v.size() % 2 == 1 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  double sum = 0;
  for (double x : v) sum += x;
  s.mean = sum / static_cast<double>(v.size());
  double ss = 0;
  for (double x : v) ss += (x - s.mean) * (x - s.mean);
  const double sd = v.size() > 1 ? std::sqrt(ss / static_cast<double>(v.size() - 1)) : 0.0;
  s.cv = s.mean != 0 ? sd / std::abs(s.mean) : 0.0;
  s.spread = s.median != 0 ? (s.max - s.min) / std::abs(s.median) : 0.0;
  s.noise = s.median != 0
                ? t_factor(v.size()) * 1.2533 * sd / std::sqrt(static_cast<double>(v.size())) / std::abs(s.median)
                : 0.0;
  return s;
}

json spread_json(const Spread& s, const std::vector<double>& values) {
  return json{{"median", s.median}, {"min", s.min},     {"max", s.max}, {"mean", s.mean},  {"cv", s.cv},
              {"spread", s.spread}, {"noise", s.noise}, {"n", s.n},     {"values", values}};
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::string full(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

std::string pct(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f%%", 100.0 * v);
  return buf;
}

std::string ratio_str(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", v);
  return buf;
}

std::optional<double> num(const json& j, const char* key) {
  if (j.is_object() && j.contains(key) && j[key].is_number()) return j[key].get<double>();
  return std::nullopt;
}

json default_targets() {
  return json{
      {"los_evals_per_s_per_core", {{"min", 10e6}, {"source", "README: >= 10 M LOS evaluations/s per core"}}},
      {"los_study_speedup_2t", {{"min", 1.85}, {"source", "issue 19: >= 1.85x from 1 to 2 threads for a whole LOS run"}}},
      {"balancing_run_ms", {{"max", 5.0}, {"source", "README: one balancing run <= 5 ms per core"}}},
      {"gimbal_measurement36_ms", {{"max", 50.0}, {"source", "bench/gimbal_bench.cc: <= 50 ms per measurement"}}},
  };
}

}  // namespace poise::nightly
