// The worked closed-form kind (src/kinds/shaft_sag/): its formula against an independent
// numerical double integration of the beam equation, its limits, and a run of its example
// study whose every row is recomputed from the row's own drawn inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "kinds/shaft_sag/shaft_sag.h"
#include "test_util.h"

using namespace poise::kinds::shaft_sag;  // the kinds' and model files' own namespaces

namespace poise {
namespace {
using kinds::shaft_sag::shaft_sag;
using test::read_text;
using test::source_path;
using test::TempDir;

// Downward deflection d and slope d' at x = a of a pinned-pinned beam under P at a, from
// d'' = -M(x) / (E I) integrated twice by the trapezoid rule on a grid with a node at a (the
// moment's kink), with d(0) = d(L) = 0.
std::pair<double, double> numerical_sag(double L, double a, double ei, double P) {
  const int n1 = 100000, n2 = 100000;
  std::vector<double> x;
  for (int i = 0; i <= n1; ++i) x.push_back(a * i / n1);
  for (int j = 1; j <= n2; ++j) x.push_back(a + (L - a) * j / n2);
  const double ra = P * (L - a) / L;
  auto curvature = [&](double s) { return -(ra * s - (s > a ? P * (s - a) : 0.0)) / ei; };
  std::vector<double> slope(x.size(), 0.0), d(x.size(), 0.0);
  for (std::size_t i = 1; i < x.size(); ++i) {
    const double h = x[i] - x[i - 1];
    slope[i] = slope[i - 1] + 0.5 * h * (curvature(x[i - 1]) + curvature(x[i]));
    d[i] = d[i - 1] + 0.5 * h * (slope[i - 1] + slope[i]);
  }
  const double c = -d.back() / L;  // the slope at 0 that brings d(L) to zero
  return {d[n1] + c * a, slope[n1] + c};
}

TEST(ShaftSag, AgreesWithANumericalIntegrationOfTheBeamEquation) {
  const double pi = 3.14159265358979323846;
  const double L = 0.056, d = 0.008, bore = 0.003, E = 200e9, P = 1.4709975;
  const double ei = E * pi * (std::pow(d, 4) - std::pow(bore, 4)) / 64.0;
  for (double a : {0.005, 0.020, 0.028, 0.041}) {
    const auto s = shaft_sag(L, a, d, bore, E, P);
    const auto [nd, ns] = numerical_sag(L, a, ei, P);
    EXPECT_NEAR(s.deflection, nd, 1e-8 * std::abs(nd)) << "a = " << a;
    EXPECT_NEAR(s.slope, ns, 1e-7 * std::abs(nd / L) + 1e-18) << "a = " << a;
  }
}

TEST(ShaftSag, LimitsAndSymmetry) {
  const double L = 0.1, d = 0.01, E = 70e9, P = 10.0;
  const double ei = E * 3.14159265358979323846 * std::pow(d, 4) / 64.0;
  const auto mid = shaft_sag(L, L / 2, d, 0.0, E, P);
  EXPECT_NEAR(mid.deflection, P * L * L * L / (48.0 * ei), 1e-15);  // the textbook mid-span case
  EXPECT_NEAR(mid.slope, 0.0, 1e-15);
  const auto left = shaft_sag(L, 0.3 * L, d, 0.0, E, P), right = shaft_sag(L, 0.7 * L, d, 0.0, E, P);
  EXPECT_NEAR(left.deflection, right.deflection, 1e-15);
  EXPECT_NEAR(left.slope, -right.slope, 1e-15);
  EXPECT_EQ(shaft_sag(L, 0.0, d, 0.0, E, P).deflection, 0.0);  // a load on the bearing
}

// The example study's text for a copy elsewhere: its model by absolute path.
std::string example_study_text() {
  std::string model = "\"";
  model.append(source_path("models/shaft_sag_example.toml")).append("\"");
  return test::replace_once(read_text(source_path("studies/shaft_sag_example.toml")),
                            "\"../models/shaft_sag_example.toml\"", model);
}

std::vector<std::map<std::string, std::string>> read_csv(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string c; std::getline(hs, c, ',');) header.push_back(c);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::map<std::string, std::string> row;
    std::size_t k = 0;
    for (std::string c; std::getline(ss, c, ',') && k < header.size(); ++k) row[header[k]] = c;
    rows.push_back(row);
  }
  return rows;
}

TEST(ShaftSag, ExampleStudyRowsFollowFromTheirInputs) {
  TempDir dir;
  const std::string out = dir.file("run");
  const auto r = test::run_poise(dir, "run '" + source_path("studies/shaft_sag_example.toml") +
                                          "' --samples 64 --threads 2 --quiet --no-plots --out '" + out + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto rows = read_csv(out + "/samples.csv");
  ASSERT_EQ(rows.size(), 64u);
  EXPECT_EQ(rows[0].count("solver_steps"), 0u);  // no solver, no solver column
  for (const auto& row : rows) {
    ASSERT_EQ(row.at("status"), "ok");
    const double a = std::stod(row.at("load_position_mm")) * 1e-3, d = std::stod(row.at("diameter_mm")) * 1e-3;
    const double E = std::stod(row.at("youngs_modulus_GPa")) * 1e9, m = std::stod(row.at("load_mass_g")) * 1e-3;
    const auto s = shaft_sag(0.056, a, d, 0.0, E, m * 9.80665);
    EXPECT_NEAR(std::stod(row.at("tilt_urad")), s.slope * 1e6, 1e-9 * std::abs(s.slope * 1e6) + 1e-12);
    EXPECT_NEAR(std::stod(row.at("los_error_arcsec")), 2.0 * std::abs(s.slope) * 206264.80624709636, 1e-9);
    EXPECT_NEAR(std::stod(row.at("deflection_um")), s.deflection * 1e6, 1e-12);
  }
  const auto summary = nlohmann::json::parse(read_text(out + "/summary.json"));
  EXPECT_FALSE(summary.contains("solver"));
  EXPECT_EQ(summary["outputs"]["tilt_urad"]["unit"], "urad");
  EXPECT_EQ(summary["requirements"].size(), 1u);
  EXPECT_EQ(summary["sweeps"][0]["points"].size(), 4u);
}

TEST(ShaftSag, SensitivityHasNoWithinSampleGroup) {
  TempDir dir;
  const std::string out = dir.file("sens");
  const auto r = test::run_poise(dir, "sensitivity '" + source_path("studies/shaft_sag_example.toml") +
                                          "' --base 16 --threads 2 --quiet --no-plots --out '" + out + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto summary = nlohmann::json::parse(read_text(out + "/summary.json"));
  // 4 toleranced parameters: base x (4 + 2) rows, and no "(within-sample randomness)" group.
  EXPECT_EQ(summary["sampling"]["samples"].get<std::size_t>(), 16u * 6u);
  EXPECT_EQ(summary.dump().find("within-sample randomness"), std::string::npos);
}

// Contributions of a kind without a runner of its own: each tolerance set to zero in turn (a
// range has no zero and says so); with the load position or the mass fixed the spread of the
// LOS error shrinks, so its p99.73 drops (Young's modulus, a range, dominates it).
TEST(ShaftSag, ContributionsZeroEachToleranceInTurn) {
  TempDir dir;
  std::string text = example_study_text();
  test::write_text(dir.file("c.toml"), text + "\n[output]\ncontribution_samples = 512\n");
  const std::string out = dir.file("run");
  const auto r = test::run_poise(dir, "run '" + dir.file("c.toml") + "' --samples 512 --threads 2 -q --out '" + out + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto s = nlohmann::json::parse(read_text(out + "/summary.json"));
  const auto& c = s["contributions"];
  ASSERT_EQ(c.size(), 5u);  // all, then the four toleranced parameters
  std::map<std::string, nlohmann::json> by;
  for (const auto& e : c) by[e["without"].get<std::string>()] = e;
  ASSERT_TRUE(by.count("tolerances.load_position"));
  EXPECT_TRUE(by["tolerances.youngs_modulus"].contains("skipped"));  // a range: no zero
  const double all = c[0]["outputs"]["los_error_arcsec"]["p99_73"]["value"].get<double>();
  const double fixed = by["tolerances.load_position"]["outputs"]["los_error_arcsec"]["p99_73"]["value"].get<double>();
  EXPECT_LT(fixed, all);
  EXPECT_LT(by["tolerances.load_mass"]["outputs"]["los_error_arcsec"]["p99_73"]["value"].get<double>(), all);
  // The same samples with nothing zeroed are the main run's (common random numbers).
  EXPECT_DOUBLE_EQ(all, s["outputs"]["los_error_arcsec"]["p99_73"]["value"].get<double>());
  EXPECT_NE(read_text(out + "/report.html").find("Which tolerance drives the error"), std::string::npos);
}

TEST(ShaftSag, DrawOffTheShaftFailsItsSampleWithTheReason) {
  TempDir dir;
  std::string text = example_study_text();
  text = test::replace_once(text, "[[requirement]]", "[overrides]\n\"parameters.load_position\" = \"56 mm\"\n\n[[requirement]]");
  test::write_text(dir.file("off.toml"), text);
  const auto r = test::run_poise(dir, "run '" + dir.file("off.toml") + "' --samples 8 --quiet --no-plots --out '" +
                                          dir.file("run") + "'");
  EXPECT_EQ(r.status, 1);  // about half the draws land past the bearing: more than 5% fail
  EXPECT_NE(read_text(dir.file("run") + "/samples.csv").find("load off the shaft"), std::string::npos);
}

}  // namespace
}  // namespace poise
