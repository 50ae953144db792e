#pragma once
/// What the modes of poise_nightly_compare share (the tool: main.cc): exit statuses, the input
/// error, JSON files, statistics over repetitions, number formatting and the default targets.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace poise::nightly {

using json = nlohmann::ordered_json;

constexpr int kExitOk = 0;
constexpr int kExitInput = 2;
constexpr int kExitRegression = 3;

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

json read_json(const std::string& path);
void write_json(const std::string& path, const json& j);
double parse_double(const std::string& s, const std::string& what);

// ---------------------------------------------------------------------------------------------
// Statistics over repetitions.

struct Spread {
  std::size_t n = 0;
  double median = 0, min = 0, max = 0, mean = 0, cv = 0, spread = 0;
  // Relative standard error of the median, 1.2533 sd / sqrt(n) / median (the median of n normal
  // draws), times t(0.975, n - 1) / 1.96: the sd is itself estimated from n draws (x1.42 for
  // n = 5, x6.5 for n = 2). The sample sd: one disturbed repetition widens it (conservative).
  double noise = 0;
};

// Student-t 97.5 % quantile over the normal one, for n - 1 degrees of freedom.
double t_factor(std::size_t n);
Spread spread_of(std::vector<double> v);
json spread_json(const Spread& s, const std::vector<double>& values);

// ---------------------------------------------------------------------------------------------
// Number formatting (%.4g, %.12g, percent with one decimal, %.3f) and a number read from JSON.

std::string fmt(double v);
std::string full(double v);
std::string pct(double v);
std::string ratio_str(double v);
std::optional<double> num(const json& j, const char* key);

// The README's absolute targets of the derived figures (a reference file's "targets" replace them).
json default_targets();

}  // namespace poise::nightly
