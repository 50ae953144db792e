// Sobol indices per model tolerance (issue 21): the columns of one tolerance (amplitude and
// phase, each bearing) as one closed group, laid out by the design's extra Saltelli groups and
// estimated by the same pick-freeze estimators (sampling/sensitivity.h), against a function
// whose group indices are known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/results/sensitivity_output.h"
#include "sampling/design.h"

namespace {

using poise::sampling::Design;
using poise::sampling::SamplingMethod;
namespace ps = poise::sampling;

constexpr double kIa = 7.0, kIb = 0.1;  // Ishigami's a and b


// Ishigami plus an interaction: f = sin x1 (1 + b x3^4) + a sin^2 x2 + c x2 x4, x_i uniform on
// [-pi, pi]. Tolerance G1 = {x1, x3} and G2 = {x2, x4} enter additively, so their closed
// indices are S = ST = V_G / V with V_G1 = V1 + V13, V_G2 = V2 + V24 and V = V_G1 + V_G2:
//   V1 = (1 + b pi^4 / 5)^2 / 2, V13 = b^2 pi^8 (1/18 - 1/50), V2 = a^2 / 8,
//   V24 = c^2 Var(x2) Var(x4) = c^2 (pi^2 / 3)^2 (E x2 = E x4 = 0).
// Per column the first-order indices sum to (V1 + V2) / V < 1 (x3 and x4 act only through
// interactions), per tolerance to 1.
TEST(SobolPerTolerance, ClosedGroupIndicesMatchTheirClosedForm) {
  const double pi = std::numbers::pi, c = 1.5;
  const double v1 = 0.5 * std::pow(1 + kIb * std::pow(pi, 4) / 5, 2), v13 = kIb * kIb * std::pow(pi, 8) * (1.0 / 18 - 1.0 / 50);
  const double v2 = kIa * kIa / 8, v24 = c * c * std::pow(pi * pi / 3, 2);
  const double v = v1 + v13 + v2 + v24;
  auto f = [&](std::span<const double> u) {
    const double x1 = -pi + 2 * pi * u[0], x2 = -pi + 2 * pi * u[1], x3 = -pi + 2 * pi * u[2], x4 = -pi + 2 * pi * u[3];
    return std::sin(x1) * (1 + kIb * std::pow(x3, 4)) + kIa * std::sin(x2) * std::sin(x2) + c * x2 * x4;
  };
  // The engine's path: tolerance keys per column -> closed groups -> the design's extra groups.
  const std::vector<std::string> columns = {"x1", "x2", "x3", "x4"};
  const poise::engine::ToleranceGroups tol = poise::engine::tolerance_groups(columns, {"G1", "G2", "G1", ""});
  ASSERT_EQ(tol.names, (std::vector<std::string>{"G1", "G2", "x4"}));  // "" = a tolerance of its own
  const poise::engine::ToleranceGroups tol2 = poise::engine::tolerance_groups(columns, {"G1", "G2", "G1", "G2"});
  ASSERT_EQ(tol2.closed_groups(), (std::vector<std::vector<std::size_t>>{{0, 2}, {1, 3}}));
  const std::size_t n = 8192;
  ps::DesignOptions o;
  o.saltelli_base = n;
  o.saltelli_extra_groups = tol2.closed_groups();
  const Design d(SamplingMethod::kSobol, 17, n * (4 + 2 + 2), 4, o);
  std::vector<double> values(d.size()), u(4);
  for (std::size_t i = 0; i < d.size(); ++i) {
    d.point(i, u);
    values[i] = f(u);
  }
  // Extra group 1 (sample block 2 + 4 + 1) takes x2 and x4 from B, x1 and x3 from A.
  std::vector<double> a(4), b(4), ab(4);
  d.point(0, a);
  d.point(n, b);
  d.point(7 * n, ab);
  EXPECT_EQ(ab, (std::vector<double>{a[0], b[1], a[2], b[3]}));
  const nlohmann::json s = poise::engine::sensitivity_json({"f"}, columns, n, {values}, 5, tol2);
  const nlohmann::json& out = s["outputs"]["f"];
  ASSERT_EQ(out["indices"].size(), 4u);  // the per-column detail stays
  ASSERT_EQ(out["tolerances"].size(), 2u);
  auto check = [&](const nlohmann::json& e, double truth, const char* what) {
    SCOPED_TRACE(std::string(e["group"].get<std::string>()) + " " + what);
    const double lo = e[what]["ci95"][0].get<double>(), hi = e[what]["ci95"][1].get<double>();
    EXPECT_LE(lo, truth);
    EXPECT_GE(hi, truth);
    EXPECT_LT(hi - lo, 0.1);  // an interval that says something
  };
  for (const auto& e : out["tolerances"]) {
    const double truth = e["group"] == "G1" ? (v1 + v13) / v : (v2 + v24) / v;
    EXPECT_EQ(e["columns"], 2u);
    check(e, truth, "first");
    check(e, truth, "total");
  }
  // Per tolerance the first-order indices sum to 1 (no interaction between tolerances), per
  // column to (V1 + V2) / V = 0.47.
  const nlohmann::json& ts = out["tolerance_first_sum"];
  EXPECT_LE(ts["ci95"][0].get<double>(), 1.0);
  EXPECT_GE(ts["ci95"][1].get<double>(), 1.0);
  EXPECT_LE(out["first_sum"]["ci95"][0].get<double>(), (v1 + v2) / v);
  EXPECT_GE(out["first_sum"]["ci95"][1].get<double>(), (v1 + v2) / v);
  EXPECT_LT(out["first_sum"]["ci95"][1].get<double>(), 0.8);
}


}  // namespace
