// A model key of a balancing campaign's design study calibrated from the machine's influence
// coefficients ([design.calibrate], cli/balance_calibration.h). The "real" machines are machines
// of the study itself, each drawn with a seed of its own at a known lever of sensor 2 (280 mm
// where the model says 250): their coefficients are written as a campaign's readings (in N, as
// the machine's force sensors give them), and the lever is calibrated from them. The interval
// value +- 1.96 se must cover the known lever in about 95% of the machines (the study run at 32
// machines per value), and the fit must move the study from its own 250 mm towards it.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/balance_command.h"
#include "core/error.h"
#include "engine/kind_interface/study_kind.h"
#include "engine/study_files/study_config.h"
#include "test_util.h"

namespace poise {
namespace {
using test::source_path;
using test::TempDir;

constexpr double kTrueLeverMm = 280.0;

// The Wang 2014 machine with the fast steady-state response (the same linear equations).
void write_study(TempDir& dir, std::size_t samples) {
  std::string model = test::read_text(source_path("models/balancing_machine_wang2014.toml"));
  model.replace(model.find("[solver]\n"), 9, "[solver]\nresponse = \"steady_state\"\n");
  test::write_text(dir.file("machine.toml"), model);
  test::write_text(dir.file("study.toml"), fmt::format(R"([study]
name = "calibration_trial"
kind = "balancing_machine"
model = "machine.toml"
[sampling]
method = "monte_carlo"
samples = {}
seed = 7
[procedure]
plane_1_surface = 2
plane_2_surface = 6
estimator = "influence"
calibration_mass = "100 g"
calibration_radius = "50 mm"
[[experiment]]
name = "cal"
type = "calibration"
)",
                                                       samples));
}

// One machine of the study at the known lever, drawn with `seed`: its coefficients |C| (N/(kg m)).
std::map<std::string, double> one_machine(const std::string& study, std::uint64_t seed) {
  const engine::StudyConfig cfg = engine::load_study(study);
  const engine::StudyKind& kind = engine::study_kind(cfg.kind);
  const engine::McResult sim =
      kind.evaluate(cfg, {{"torsional_plate.lever", fmt::format("{} mm", kTrueLeverMm)}}, 1, seed, 1);
  std::map<std::string, double> c;
  for (const std::string n : {"s1_p1", "s1_p2", "s2_p1", "s2_p2"}) c[n] = sim.values[sim.index("cal_" + n + "_N_per_kgm")].at(0);
  return c;
}

// A campaign of three runs (bare, 100 g at 50 mm in each plane) whose readings those coefficients
// give, the rotor's own reading 20 mN; phases of its own (only magnitudes are fitted).
void write_campaign(TempDir& dir, const std::map<std::string, double>& c, std::size_t samples,
                    const std::string& range = "[\"200 mm\", \"340 mm\"]") {
  using cd = std::complex<double>;
  const cd a0[2] = {std::polar(0.02, 0.3), std::polar(0.02, 1.1)};
  auto h = [&](int s, int p) {  // N per gram at 50 mm
    return std::polar(c.at(fmt::format("s{}_p{}", s, p)) * 1e-3 * 0.05, 0.7 * s + 0.4 * p);
  };
  std::string csv = "run,one_re,one_im,two_re,two_im\n";
  for (int run = 1; run <= 3; ++run) {
    csv += std::to_string(run);
    for (int s = 1; s <= 2; ++s) {
      const cd z = a0[s - 1] + (run == 1 ? cd(0.0) : h(s, run - 1) * 100.0);
      csv += fmt::format(",{:.17g},{:.17g}", z.real(), z.imag());
    }
    csv += "\n";
  }
  test::write_text(dir.file("readings.csv"), csv);
  std::string toml = R"([campaign]
name = "one machine of the study"
readings = "readings.csv"
amplitude_unit = "N"
[[sensor]]
name = "one"
real = "one_re"
imaginary = "one_im"
[[sensor]]
name = "two"
real = "two_re"
imaginary = "two_im"
[[plane]]
name = "p1"
radius = "50 mm"
[[plane]]
name = "p2"
radius = "50 mm"
[[run]]
name = "bare"
masses = []
[[run]]
name = "p1 trial"
masses = [{plane = "p1", mass = "100 g", angle = "0 deg"}]
[[run]]
name = "p2 trial"
masses = [{plane = "p2", mass = "100 g", angle = "0 deg"}]
[design]
study = "study.toml"
)";
  toml += fmt::format("samples = {}\n", samples);
  for (int s = 1; s <= 2; ++s) {
    for (int p = 1; p <= 2; ++p) {
      toml += fmt::format(
          "[[design.compare]]\nfigure = \"influence\"\nsensor = \"{}\"\nplane = \"p{}\"\noutput = "
          "\"cal_s{}_p{}_N_per_kgm\"\n",
          s == 1 ? "one" : "two", p, s, p);
    }
  }
  toml += "[design.calibrate]\nkey = \"torsional_plate.lever\"\nrange = " + range + "\n";
  test::write_text(dir.file("campaign.toml"), toml);
}

TEST(BalanceCalibration, TheLeverOfOneMachineIsRecoveredWithinItsInterval) {
  TempDir dir;
  constexpr std::size_t kSamples = 16;
  write_study(dir, kSamples);
  const auto c = one_machine(dir.file("study.toml"), 101);
  write_campaign(dir, c, kSamples);
  const cli::BalanceResult r = cli::balance_campaign(dir.file("campaign.toml"), dir.file("out"));
  ASSERT_TRUE(r.analyses.calibration.has_value());
  const auto& k = *r.analyses.calibration;
  EXPECT_EQ(k.key, "torsional_plate.lever");
  EXPECT_EQ(k.unit, "mm");
  EXPECT_FALSE(k.at_bound);
  EXPECT_NEAR(k.value, kTrueLeverMm, 3.0 * k.se);
  EXPECT_GT(k.se, 0.0);
  EXPECT_LT(k.se, 30.0);
  EXPECT_LT(k.chi2_after, k.chi2_before);
  ASSERT_EQ(k.figures.size(), 4u);
  // Sensor 2 reads F l_2 / l: its coefficients follow the lever, sensor 1's hardly.
  for (const auto& f : k.figures) {
    if (f.sensor == "two") {
      EXPECT_LT(std::abs(f.after - f.real), std::abs(f.before - f.real)) << f.output;
    }
  }
  EXPECT_NE(r.analyses.speeds.front().answer.find("calibrated"), std::string::npos);
  const std::string html = test::read_text(dir.file("out/report.html"));
  EXPECT_NE(html.find("Calibration of the design study"), std::string::npos);
  const auto j = nlohmann::json::parse(test::read_text(dir.file("out/balance.json")));
  EXPECT_EQ(j["calibration"]["label"], "calibration");
  EXPECT_NEAR(j["calibration"]["value"].get<double>(), k.value, 1e-12);
}

// Coverage of value +- 1.96 se over machines drawn at the known lever (a battery: many
// calibrations of the study; the ctest label `battery`, CMakeLists.txt).
TEST(BalanceCalibration, CoverageOfTheLeverOverMachinesOfTheStudy) {
  TempDir dir;
  constexpr std::size_t kSamples = 32;
  constexpr int kMachines = 100;
  write_study(dir, kSamples);
  int covered = 0;
  for (int m = 0; m < kMachines; ++m) {
    write_campaign(dir, one_machine(dir.file("study.toml"), 1000 + static_cast<std::uint64_t>(m)), kSamples);
    const cli::BalanceResult r = cli::balance_campaign(dir.file("campaign.toml"), "");
    ASSERT_TRUE(r.analyses.calibration.has_value());
    const auto& k = *r.analyses.calibration;
    covered += std::abs(k.value - kTrueLeverMm) <= 1.96 * k.se ? 1 : 0;
  }
  // 95% nominal; at 100 machines the binomial's 99.9% band reaches down to 88 (measured: 288 of
  // 300 machines at 32 samples; at 16 samples 276 of 300, 92%).
  EXPECT_GE(covered, 88) << covered << " of " << kMachines;
}

TEST(BalanceCalibration, AKeyTheModelLacksIsRefusedWithTheCampaignsLine) {
  TempDir dir;
  write_study(dir, 8);
  write_campaign(dir, one_machine(dir.file("study.toml"), 5), 8);
  std::string toml = test::read_text(dir.file("campaign.toml"));
  toml.replace(toml.find("torsional_plate.lever"), 21, "torsional_plate.levre");
  test::write_text(dir.file("campaign.toml"), toml);
  try {
    cli::balance_campaign(dir.file("campaign.toml"), "");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("[design.calibrate] torsional_plate.levre"), std::string::npos) << what;
    EXPECT_NE(what.find("campaign.toml:"), std::string::npos) << what;
  }
}

TEST(BalanceCalibration, TooFewMachinesForTheCovarianceAreRefused) {
  TempDir dir;
  write_study(dir, 6);
  write_campaign(dir, one_machine(dir.file("study.toml"), 5), 6);
  try {
    cli::balance_campaign(dir.file("campaign.toml"), "");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("samples = 6"), std::string::npos) << e.what();
  }
}

TEST(BalanceCalibration, ACalibrationWithoutInfluenceFiguresIsRefused) {
  TempDir dir;
  write_study(dir, 8);
  write_campaign(dir, one_machine(dir.file("study.toml"), 5), 8);
  std::string toml = test::read_text(dir.file("campaign.toml"));
  while (toml.find("figure = \"influence\"") != std::string::npos) {
    toml.replace(toml.find("figure = \"influence\""), 20, "figure = \"urr\"");
  }
  while (toml.find("sensor = \"") != std::string::npos) {
    const std::size_t at = toml.find("sensor = \"");
    toml.erase(at, toml.find('\n', at) + 1 - at);
  }
  test::write_text(dir.file("campaign.toml"), toml);
  try {
    cli::balance_campaign(dir.file("campaign.toml"), "");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("figure = \"influence\""), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace poise
