// Worst case, RSS and Monte Carlo side by side (engine/run/stack_up.h) on a textbook stack-up
// whose answers are printed: Drake's motor assembly (tests/data/stackups/drake_motor_assembly/
// SOURCE). The published figures (mean, worst-case limits, RSS) are checked to the digits the
// book gives; the figures it does not publish are checked against their closed form (a sum of
// independent normals is normal), never called published.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "test_util.h"

namespace poise {
namespace {
using test::read_text;
using test::source_path;
using test::TempDir;

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

nlohmann::json run_drake(TempDir& dir, std::size_t samples) {
  test::write_text(dir.file("drake.toml"),
                   "[study]\nname = \"drake\"\nkind = \"formula\"\nmodel = \"" +
                       source_path("tests/data/stackups/drake_motor_assembly/model.toml") +
                       "\"\n[sampling]\nmethod = \"monte_carlo\"\nsamples = " + std::to_string(samples) +
                       "\nseed = 3\n[[requirement]]\noutput = \"gap\"\nwithin = [\"0.04 in\", \"0.08 in\"]\n"
                       "yield_at_least = 0.5\n");
  const auto r = test::run_poise(dir, "run '" + dir.file("drake.toml") + "' --threads 2 --quiet --no-plots --out '" +
                                          dir.file("run") + "'");
  EXPECT_EQ(r.status, 0) << r.err;
  return nlohmann::json::parse(read_text(dir.file("run") + "/summary.json"));
}

TEST(StackUp, DrakesMotorAssemblyGivesItsPublishedFigures) {
  TempDir dir;
  const auto s = run_drake(dir, 20000);
  const auto& gap = s["stack_up"]["outputs"]["gap"];
  ASSERT_TRUE(gap.is_object()) << s.dump(1).substr(0, 2000);
  // Published: mean 0.0615, worst case -0.034 to 0.157 (+-0.0955), RSS 0.0234 to 0.0996 (+-0.0381).
  EXPECT_NEAR(gap["nominal"].get<double>(), 0.0615, 1e-9);
  EXPECT_NEAR(gap["worst_case"]["min"].get<double>(), -0.034, 1e-9);
  EXPECT_NEAR(gap["worst_case"]["max"].get<double>(), 0.157, 1e-9);
  EXPECT_EQ(gap["worst_case"]["corners"].get<std::size_t>(), 2048u);
  EXPECT_NEAR(gap["worst_case_linear"]["half_width"].get<double>(), 0.0955, 1e-7);
  EXPECT_NEAR(gap["rss"]["half_width"].get<double>(), 0.0381, 5e-5);
  EXPECT_NEAR(gap["rss"]["min"].get<double>(), 0.0234, 5e-5);
  EXPECT_NEAR(gap["rss"]["max"].get<double>(), 0.0996, 5e-5);
  // Closed form, not published: sd = RSS / 3 (each tolerance 3 sigma), the variance shares.
  const double sd = std::sqrt(std::pow(0.0155, 2) + std::pow(0.002, 2) + std::pow(0.003, 2) + 2 * std::pow(0.0075, 2) +
                              2 * std::pow(0.005, 2) + std::pow(0.007, 2) + std::pow(0.007, 2) + std::pow(0.006, 2) +
                              std::pow(0.03, 2)) /
                    3.0;
  EXPECT_NEAR(gap["rss"]["sd_first_order"].get<double>(), sd, 1e-9);
  const double n = 20000.0;
  EXPECT_NEAR(gap["monte_carlo"]["mean"].get<double>(), 0.0615, 4.0 * sd / std::sqrt(n));
  EXPECT_NEAR(gap["monte_carlo"]["sd"].get<double>(), sd, 4.0 * sd / std::sqrt(2.0 * n));
  // K (the tapped hole, +-0.030) holds 0.009^2 / (9 sd^2) = 62.08% of the variance.
  const std::size_t k = 10;
  EXPECT_NEAR(gap["contributions_percent"]["rss"][k].get<double>(), 100.0 * 0.0001 / (sd * sd), 1e-6);
  EXPECT_NEAR(gap["contributions_percent"]["rss"][k].get<double>(), 62.08, 0.01);
  EXPECT_NEAR(gap["contributions_percent"]["monte_carlo"][k].get<double>(), 62.08, 1.5);
  EXPECT_NEAR(gap["contributions_percent"]["monte_carlo_r2"].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(gap["contributions_percent"]["worst_case"][k].get<double>(), 100.0 * 0.030 / 0.0955, 1e-6);
  // Against [0.04, 0.08] in: the exact normal share outside and Cpk lie in the run's intervals.
  const double outside = normal_cdf((0.04 - 0.0615) / sd) + normal_cdf((0.0615 - 0.08) / sd);
  const auto& cap = gap["capability"];
  EXPECT_LE(cap["ppm_outside"]["ci95"][0].get<double>(), 1e6 * outside);
  EXPECT_GE(cap["ppm_outside"]["ci95"][1].get<double>(), 1e6 * outside);
  const double cpk = 0.0185 / (3.0 * sd);
  EXPECT_LE(cap["cpk"]["ci95"][0].get<double>(), cpk);
  EXPECT_GE(cap["cpk"]["ci95"][1].get<double>(), cpk);
  EXPECT_NEAR(s["requirements"][0]["value"].get<double>(), 1.0 - outside, 4.0 * std::sqrt(outside * (1 - outside) / n));
  EXPECT_NE(read_text(dir.file("run") + "/report.html").find("Worst case, RSS and Monte Carlo"), std::string::npos);
}

// A product of positive inputs is monotone in each of them: the corners give its exact
// extremes, which the linearised bound misses (it drops the product of the half-widths).
TEST(StackUp, CornersGiveTheExtremesTheLinearisedBoundMisses) {
  TempDir dir;
  test::write_text(dir.file("m.toml"),
                   "[model]\nkind = \"formula\"\nname = \"area\"\n[parameters]\nw = \"10 mm\"\nh = \"20 mm\"\n"
                   "[tolerances.w]\ntolerance = \"1 mm\"\ndistribution = \"uniform\"\ntolerance_is = \"bounds\"\n"
                   "[tolerances.h]\ntolerance = \"2 mm\"\ndistribution = \"uniform\"\ntolerance_is = \"bounds\"\n"
                   "[[output]]\nname = \"area\"\nunit = \"mm^2\"\nformula = \"w * h\"\n");
  test::write_text(dir.file("s.toml"), "[study]\nname = \"a\"\nkind = \"formula\"\nmodel = \"" + dir.file("m.toml") +
                                           "\"\n[sampling]\nmethod = \"monte_carlo\"\nsamples = 4000\nseed = 1\n");
  const auto r =
      test::run_poise(dir, "run '" + dir.file("s.toml") + "' --quiet --no-plots --out '" + dir.file("run") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto a = nlohmann::json::parse(read_text(dir.file("run") + "/summary.json"))["stack_up"]["outputs"]["area"];
  EXPECT_NEAR(a["worst_case"]["min"].get<double>(), 9.0 * 18.0, 1e-9);
  EXPECT_NEAR(a["worst_case"]["max"].get<double>(), 11.0 * 22.0, 1e-9);
  EXPECT_NEAR(a["worst_case_linear"]["half_width"].get<double>(), 20.0 * 1.0 + 10.0 * 2.0, 1e-6);
  EXPECT_NEAR(a["sensitivities"][0].get<double>(), 20.0, 1e-6);
  EXPECT_LT(a["contributions_percent"]["monte_carlo_r2"].get<double>(), 1.0);  // not linear
  EXPECT_GT(a["contributions_percent"]["monte_carlo_r2"].get<double>(), 0.98);
}

}  // namespace
}  // namespace poise
