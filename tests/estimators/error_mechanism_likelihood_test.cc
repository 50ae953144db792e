// The per-test error mechanisms' likelihood (estimators/error_mechanism_likelihood.h): the
// log-density against a hand computation, maximum likelihood against the closed form and
// against known sigmas on simulated tests, the mechanism picked on data made by each, and
// `poise error-mechanisms` on the Yang 2015 tables (figures and the Table 3 test-13 flag).
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <random>

#include "estimators/error_mechanism_likelihood.h"
#include "test_util.h"

namespace poise::estimators {
namespace {

constexpr double kDeg = 3.141592653589793 / 180.0;
constexpr double kPi = 3.141592653589793;

UnbalanceTestRecord test_of(double L, double a, double M, double b, int n = 36) {
  return {"T", 1, L, a, M, b, n};
}

TEST(ErrorMechanismLikelihood, LogDensityByHand) {
  // One test: L = 10 mN*m at 30 deg measured as 10.5 mN*m at 32 deg, 36 positions.
  const UnbalanceTestRecord t = test_of(10e-3, 30 * kDeg, 10.5e-3, 32 * kDeg);
  const double r = 10.5e-3 * std::cos(2 * kDeg) - 10e-3, tt = 10.5e-3 * std::sin(2 * kDeg);
  const LoadFrameError e = load_frame_error(t);
  EXPECT_NEAR(e.along, r, 1e-15);
  EXPECT_NEAR(e.across, tt, 1e-15);
  const double sp = 0.2e-3, noise = 2 * sp * sp / 36;
  MechanismSigmas s;
  s.scale = 0.03;
  s.zero = 0.5 * kDeg;
  const double vr = 1e-4 * 0.03 * 0.03 + noise, vt = 1e-4 * std::pow(0.5 * kDeg, 2) + noise;
  const double by_hand = -0.5 * (std::log(2 * kPi * vr) + r * r / vr) - 0.5 * (std::log(2 * kPi * vt) + tt * tt / vt);
  const UnbalanceTestRecord one[] = {t};
  EXPECT_NEAR(mechanism_log_likelihood(one, s, sp), by_hand, 1e-9);
  // Additive: the same sigma on both components.
  MechanismSigmas a;
  a.along = a.across = 0.4e-3;
  const double va = 0.16e-6 + noise;
  EXPECT_NEAR(mechanism_log_likelihood(one, a, sp),
              -0.5 * (2 * std::log(2 * kPi * va) + (r * r + tt * tt) / va), 1e-9);
}

TEST(ErrorMechanismLikelihood, AdditiveFitMatchesTheClosedForm) {
  // Equal n for every test: s_d^2 = mean(r^2 + t^2) / 2 - 2 sigma_p^2 / n.
  std::vector<UnbalanceTestRecord> tests;
  double sum = 0;
  const double loads[] = {5e-3, 8e-3, 12e-3, 20e-3, 25e-3};
  const double errs[][2] = {{0.9e-3, 0.2e-3}, {-0.5e-3, 0.4e-3}, {0.3e-3, -0.6e-3}, {-1.1e-3, 0.1e-3}, {0.2e-3, 0.3e-3}};
  for (int i = 0; i < 5; ++i) {
    const double a = 40.0 * i * kDeg, x = loads[i] + errs[i][0], y = errs[i][1];
    tests.push_back(test_of(loads[i], a, std::hypot(x, y), a + std::atan2(y, x)));
    sum += errs[i][0] * errs[i][0] + errs[i][1] * errs[i][1];
  }
  const double sp = 0.1e-3;
  const MechanismSigmas s = fit_mechanism(tests, ErrorMechanism::kAdditive, sp);
  const double closed = std::sqrt(sum / 10.0 - 2 * sp * sp / 36);
  EXPECT_NEAR(s.along, closed, 1e-5 * closed);  // Brent: about sqrt(machine epsilon) in sigma
  EXPECT_EQ(s.along, s.across);
  EXPECT_EQ(s.scale, 0.0);
  EXPECT_EQ(parameter_count(ErrorMechanism::kAdditive), 1);
  EXPECT_EQ(parameter_count(ErrorMechanism::kScaleZeroAndAdditive), 3);
}

// Simulated tests of a mechanism with known sigmas, loads 5-25 mN*m at random angles.
std::vector<UnbalanceTestRecord> simulate(const MechanismSigmas& s, double sp, int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> z(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<UnbalanceTestRecord> out;
  for (int i = 0; i < n; ++i) {
    const double L = 5e-3 + 20e-3 * u(rng), a = 2 * kPi * u(rng), e = std::sqrt(2 * sp * sp / 36);
    const double k = s.scale * z(rng), zz = s.zero * z(rng);
    const double x = L * (1 + k) * std::cos(zz) + s.along * z(rng) + e * z(rng);
    const double y = L * (1 + k) * std::sin(zz) + s.across * z(rng) + e * z(rng);
    out.push_back(test_of(L, a, std::hypot(x, y), a + std::atan2(y, x)));
  }
  return out;
}

TEST(ErrorMechanismLikelihood, RecoversKnownSigmasAndPicksTheTrueMechanism) {
  const double sp = 0.2e-3;
  MechanismSigmas sz;
  sz.scale = 0.04;
  sz.zero = 0.8 * kDeg;
  const auto a = simulate(sz, sp, 800, 1);
  const MechanismSigmas f = fit_mechanism(a, ErrorMechanism::kScaleAndZero, sp);
  // 800 tests: the sigma's standard error is about 1/sqrt(2 n) = 2.5%; allow 4 of them.
  EXPECT_NEAR(f.scale, 0.04, 0.1 * 0.04);
  EXPECT_NEAR(f.zero, 0.8 * kDeg, 0.1 * 0.8 * kDeg);
  EXPECT_GT(mechanism_log_likelihood(a, f, sp),
            mechanism_log_likelihood(a, fit_mechanism(a, ErrorMechanism::kAdditive, sp), sp) + 20);
  MechanismSigmas ad;
  ad.along = 0.9e-3;
  ad.across = 0.25e-3;
  const auto b = simulate(ad, sp, 800, 2);
  const MechanismSigmas g = fit_mechanism(b, ErrorMechanism::kAdditiveAlongAcross, sp);
  EXPECT_NEAR(g.along, 0.9e-3, 0.1 * 0.9e-3);
  EXPECT_NEAR(g.across, 0.25e-3, 0.1 * 0.25e-3);
  EXPECT_GT(mechanism_log_likelihood(b, g, sp),
            mechanism_log_likelihood(b, fit_mechanism(b, ErrorMechanism::kScaleAndZero, sp), sp) + 20);
  // The nesting model never does worse than either of its parts.
  const double both = mechanism_log_likelihood(a, fit_mechanism(a, ErrorMechanism::kScaleZeroAndAdditive, sp), sp);
  EXPECT_GE(both, mechanism_log_likelihood(a, f, sp) - 1e-6);
}

TEST(ErrorMechanismLikelihood, RankCorrelations) {
  const double x[] = {1, 2, 3, 4, 5}, y[] = {10, 8, 6, 4, 1}, w[] = {1, 3, 2, 5, 4};
  EXPECT_DOUBLE_EQ(spearman(x, y), -1.0);
  EXPECT_NEAR(spearman(x, w), 0.8, 1e-12);  // 1 - 6 * 4 / (5 * 24)
  EXPECT_NEAR(pearson(x, x), 1.0, 1e-12);
}

TEST(ErrorMechanismsCommand, YangTablesFiguresAndTheTable3Flag) {
  test::TempDir d;
  const auto r = test::run_poise(d, "error-mechanisms '" + test::source_path("data/yang2015") + "' --json --draws 200");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["tests"], 36);
  ASSERT_EQ(j["printed_error_checks"].size(), 1u) << j["printed_error_checks"].dump();
  const auto& c = j["printed_error_checks"][0];
  EXPECT_EQ(c["table"], "Table 3");
  EXPECT_EQ(c["test"], 13);
  EXPECT_NEAR(c["printed"].get<double>(), -1.57, 1e-9);
  EXPECT_NEAR(c["recomputed"].get<double>(), -1.92, 1e-9);
  const auto& t3 = j["rmse_recomputed"][1];
  EXPECT_EQ(t3["table"], "Table 3");
  EXPECT_NEAR(t3["rmse_angle_deg"].get<double>(), 1.92, 0.005);
  EXPECT_NEAR(t3["rmse_angle_from_printed_errors_deg"].get<double>(), 1.88, 0.005);
  // The verdict and its margins (see data/yang2015/README.md).
  EXPECT_EQ(j["supported"], "additive_along_across");
  for (const auto& m : j["joint_fit_all_tables"]) {
    if (m["mechanism"] == "scale_and_zero") {
      EXPECT_GT(m["delta_aic"].get<double>(), 30.0);
    }
    if (m["mechanism"] == "additive_along_across") {
      EXPECT_EQ(m["delta_aic"].get<double>(), 0.0);
    }
  }
  // Calibrated on Table 4, the scale error is today's kt_drift (4.4%).
  for (const auto& row : j["calibrate_on_one_validate_on_others"]) {
    if (row["calibration_table"] != "Table 4") continue;
    EXPECT_NEAR(row["mechanisms"][0]["parameters"]["kt_scale_pct"].get<double>(), 4.44, 0.05);
    EXPECT_EQ(row["mechanisms"][0]["calibration_target"]["table"], "Table 4");
    EXPECT_EQ(row["mechanisms"][0]["validation"].size(), 3u);
  }
}

TEST(ErrorMechanismsCommand, BadInputNamesFileLineAndColumn) {
  test::TempDir d;
  for (const char* f : {"table1_loading_test_36pt.csv", "tables4_5_repeatability.csv"}) {
    test::write_text(d.file(f), test::read_text(test::source_path(std::string("data/yang2015/") + f)));
  }
  test::write_text(d.file("tables2_3_loading_tests.csv"),
                   "test,circle,load_angle_deg,load_torque_mNm,measured_torque_mNm,measured_angle_deg\n"
                   "1,C_A,270.30,7.78,nine,268.46\n");
  auto r = test::run_poise(d, "error-mechanisms '" + d.path().string() + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("tables2_3_loading_tests.csv:2: column measured_torque_mNm: 'nine' (expected a finite number)"),
            std::string::npos) << r.err;
  test::write_text(d.file("tables2_3_loading_tests.csv"),
                   "test,circle,load_angle_deg,load_torque_mNm,measured_torque_mNm,measured_angle_deg\n"
                   "1,C_C,270.30,7.78,9.01,268.46\n");
  r = test::run_poise(d, "error-mechanisms '" + d.path().string() + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("column circle: 'C_C' (expected C_A or C_B)"), std::string::npos) << r.err;
  test::write_text(d.file("tables2_3_loading_tests.csv"), "test,circle,load_angle_deg\n1,C_A,270.30\n");
  r = test::run_poise(d, "error-mechanisms '" + d.path().string() + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("tables2_3_loading_tests.csv:1: no column 'load_torque_mNm' (expected it in the header)"),
            std::string::npos) << r.err;
  test::write_text(d.file("tables2_3_loading_tests.csv"),
                   test::read_text(test::source_path("data/yang2015/tables2_3_loading_tests.csv")));
  test::write_text(d.file("tables4_5_repeatability.csv"),
                   "points,repeat,load_angle_deg,load_torque_mNm,measured_torque_mNm,measured_angle_deg\n"
                   "24,1,45.50,12.91,12.07,46.69\n");
  r = test::run_poise(d, "error-mechanisms '" + d.path().string() + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("tables4_5_repeatability.csv:2: column points: 24 (expected 36 (Table 4) or 18 (Table 5))"),
            std::string::npos) << r.err;
  r = test::run_poise(d, "error-mechanisms '" + test::source_path("data/yang2015") + "' --calibrate 'Table 9'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--calibrate \"Table 9\": no such table"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace poise::estimators
