// The residual diagnosis on data Poise did not make (tests/support/independent_gimbal_data.h: its own
// gimbal equation, servo, RK4, ADC and encoder, turntable plans). Measured here: detection of
// planted effects, the false-positive rate over many noise realisations, "never worse beyond
// its uncertainty", confounded plans reported as ambiguous rather than resolved silently, and
// an effect outside the candidate list flagged as unexplained structure.
//
// The truth for the unbalance estimate is the base fit of the noise-free clean table of the
// same plan (the generator's own small systematic terms, e.g. the oscillation's mean angle,
// are then not counted as diagnosis errors).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include <Eigen/Dense>

#include "estimators/oscillation_diagnosis.h"
#include "estimators/residual_diagnosis.h"
#include "estimators/sine_fit.h"
#include "diagnosis_scoring.h"
#include "independent_gimbal_data.h"

namespace poise::estimators {
namespace {

namespace td = poise::testdata;
using scoring::to_table;
constexpr double kPi = std::numbers::pi;

struct Truth {
  double amplitude, phase;  // mN*m, rad
};

Truth truth_of(const std::vector<td::Visit>& plan) {
  const std::vector<double> m = td::position_torques({}, {}, {}, plan);
  const TorqueTable t = to_table(td::make_table(plan, m, {0.0, 0.0}, 1));
  const SineFitResult f = fit_sine(t.theta_rad, t.torque);
  return {f.amplitude, f.phase};
}

double vector_error(const UnbalanceEstimate& e, const Truth& t) {
  return std::hypot(e.amplitude * std::cos(e.phase) - t.amplitude * std::cos(t.phase),
                    e.amplitude * std::sin(e.phase) - t.amplitude * std::sin(t.phase));
}

bool mentions(const DiagnosisResult& r, const std::string& name) {
  for (const Effect& e : r.effects) {
    if (e.name == name) return true;
  }
  for (const AmbiguousFinding& a : r.ambiguous) {
    for (const Reading& rd : a.readings) {
      if (rd.effects.find(name) != std::string::npos) return true;
    }
  }
  return false;
}

// Counts over noise realisations of one planted scenario.
struct Tally {
  int runs = 0, found = 0, worse = 0, any_effect = 0, flagged = 0;
  double err_before = 0.0, err_after = 0.0;  // mean vector errors, mN*m
};

Tally run(const std::vector<td::Visit>& plan, const td::Plant& p, const td::TimeEffects& e,
          const td::TableNoise& noise, int n, std::uint64_t seed0, const std::string& effect,
          const DiagnosisOptions& opt = {}) {
  const Truth truth = truth_of(plan);
  const std::vector<double> m = td::position_torques(p, {}, e, plan);
  Tally t;
  for (int k = 0; k < n; ++k) {
    const TorqueTable table = to_table(td::make_table(plan, m, noise, seed0 + k));
    const DiagnosisResult r = diagnose_residuals(table, opt);
    const double before = vector_error(r.estimate_before, truth);
    const double after = vector_error(r.estimate_after, truth);
    ++t.runs;
    t.found += !effect.empty() && mentions(r, effect);
    t.any_effect += !r.effects.empty();
    t.flagged += r.omnibus.unexplained;
    // Never worse beyond the uncertainty: the error after exceeds the one before by more than
    // two standard errors of the reported estimate.
    t.worse += after > before + 2.0 * r.estimate_after.se_amplitude;
    t.err_before += before / n;
    t.err_after += after / n;
  }
  std::printf("  %-34s found %2d/%d, any effect %2d, flagged %2d, worse %d; mean error %.3f -> "
              "%.3f mN*m\n",
              effect.empty() ? "(clean)" : effect.c_str(), t.found, t.runs, t.any_effect,
              t.flagged, t.worse, t.err_before, t.err_after);
  return t;
}

TEST(IndependentData, GeneratorMatchesItsClosedFormLimit) {
  // Mean over whole periods of U sin(theta + b + phi), phi = a (1 - cos w t):
  // U J0(a) sin(theta + b + a); the dynamic terms average out, so the table is that plus M_0.
  const td::Plant p;
  const td::Servo s;
  const double a = s.amplitude * s.period / (2.0 * kPi);
  const std::vector<td::Visit> plan = td::forward_sweep();
  const std::vector<double> m = td::position_torques(p, s, {}, plan);
  const TorqueTable t = to_table(td::make_table(plan, m, {0.0, 0.0}, 1));
  const SineFitResult f = fit_sine(t.theta_rad, t.torque);
  EXPECT_NEAR(f.amplitude, p.unbalance * 1e3 * std::cyl_bessel_j(0.0, a), 2e-3);
  EXPECT_NEAR(f.phase, p.phase_rad + a, 2e-4);
  EXPECT_NEAR(f.offset, p.constant * 1e3, 2e-3);
  EXPECT_LT(f.rmse, 2e-3);  // ADC quantisation and the servo's residual only
}

TEST(IndependentData, CleanTablesRarelyGetAnEffectOrAFlag) {
  int runs = 0, any = 0, flagged = 0;
  const td::TableNoise white{0.2e-3, 0.0};
  for (const auto& plan : {td::forward_sweep(), td::forward_and_back(), td::split_sweep(),
                           td::shuffled(7)}) {
    const Tally t = run(plan, {}, {}, white, 40, 100, "");
    runs += t.runs, any += t.any_effect, flagged += t.flagged;
    EXPECT_EQ(t.worse, 0);
  }
  const double allowance = 2.0 * std::sqrt(0.05 * 0.95 / runs);
  std::printf("clean tables: an effect in %d of %d (%.3f), unexplained structure in %d (%.3f)\n",
              any, runs, static_cast<double>(any) / runs, flagged,
              static_cast<double>(flagged) / runs);
  EXPECT_LE(static_cast<double>(any) / runs, 0.05 + allowance);
  EXPECT_LE(static_cast<double>(flagged) / runs, 0.05 + allowance);
}

TEST(IndependentData, StepHalfwayIsFoundAndNotLeftInTheEstimate) {
  td::TimeEffects e;
  e.step = 1.6e-3, e.step_time = 18 * 60.0 - 1.0;  // re-zeroed amplifier before position 18
  const Tally t = run(td::forward_sweep(), {}, e, {0.2e-3, 0.0}, 20, 200, "step");
  EXPECT_GE(t.found, 18);
  EXPECT_EQ(t.worse, 0);
  EXPECT_LT(t.err_after, 0.5 * t.err_before);
}

TEST(IndependentData, FastSaturatingDriftIsNotMadeWorse) {
  td::TimeEffects e;
  e.settle = 1.5e-3, e.settle_tau = 240.0;  // thermal settling over the first minutes
  const Tally t = run(td::forward_sweep(), {}, e, {0.2e-3, 0.0}, 20, 300, "exponential_drift");
  EXPECT_GE(t.found, 16);
  EXPECT_EQ(t.worse, 0);
  EXPECT_LE(t.err_after, t.err_before + 0.05);
}

TEST(IndependentData, TorqueConstantDriftIsNotMadeWorse) {
  td::TimeEffects e;
  e.kt_rate = -0.06 / 2160.0;  // K_T falls 6 % over the run (about 60 K of magnet heating)
  const Tally t = run(td::forward_sweep(), {}, e, {0.2e-3, 0.0}, 20, 400, "kt_drift");
  EXPECT_GE(t.found, 16);
  // Before the time-shape window: 1 of these 20 (seed 401) worse beyond 2 SE, the drift read
  // as a step (K_T-drift reading 3.5 BIC behind, r = 0.83).
  EXPECT_EQ(t.worse, 0);
  EXPECT_LE(t.err_after, t.err_before + 0.05);
}

TEST(IndependentData, DirectionOffsetOnASplitSweepIsNotResolvedSilently) {
  td::Plant p;
  p.direction_offset = 0.4e-3;  // cable wind-up: +-0.4 mN*m by approach direction
  const Tally t = run(td::split_sweep(), p, {}, {0.2e-3, 0.0}, 20, 500, "direction_offset");
  EXPECT_GE(t.found, 18);
  EXPECT_EQ(t.worse, 0);
}

TEST(IndependentData, CorrelatedNoiseOnAOneDirectionSweepIsNotReportedAsHarmonicsAlone) {
  const std::vector<td::Visit> plan = td::forward_sweep();
  const std::vector<double> m = td::position_torques({}, {}, {}, plan);
  int silent = 0, harmonics = 0;
  for (int k = 0; k < 30; ++k) {
    const DiagnosisResult r =
        diagnose_residuals(to_table(td::make_table(plan, m, {0.15e-3, 0.85}, 600 + k)));
    for (std::size_t i = 0; i < r.effects.size(); ++i) {
      if (r.effects[i].name != "harmonic") continue;
      ++harmonics;
      bool has_ar_reading = false;
      for (const auto& a : r.ambiguous) {
        for (const auto& rd : a.readings) has_ar_reading |= rd.effects.find("autocorrelation") == 0;
      }
      const bool ar_found = mentions(r, "autocorrelation");
      silent += !(has_ar_reading || ar_found);
    }
  }
  std::printf("AR(1) noise, one-direction sweep: %d harmonics reported, %d without the "
              "autocorrelation reading\n",
              harmonics, silent);
  EXPECT_EQ(silent, 0);
}

TEST(IndependentData, StepAtTheSplitOfASplitSweepIsNotReportedAsADirectionOffsetAlone) {
  td::TimeEffects e;
  e.step = 1.0e-3, e.step_time = 19 * 60.0 - 1.0;  // a knock while the cable is unwound
  const std::vector<td::Visit> plan = td::split_sweep();
  const std::vector<double> m = td::position_torques({}, {}, e, plan);
  int silent = 0;
  for (int k = 0; k < 10; ++k) {
    const DiagnosisResult r = diagnose_residuals(to_table(td::make_table(plan, m, {0.2e-3, 0.0}, 800 + k)));
    bool direction = false, step_reading = false;
    for (const Effect& x : r.effects) direction |= x.name == "direction_offset";
    for (const auto& a : r.ambiguous) {
      for (const auto& rd : a.readings) step_reading |= rd.effects.find("step") == 0;
    }
    silent += direction && !step_reading;
  }
  EXPECT_EQ(silent, 0);
}

// Correlated noise on a one-direction sweep makes wanders that a step or an outlier fits
// (before the search-disagreement reading: 3 of these 40 tables worse beyond 2 SE, a step
// moving the estimate by 4-7 SE).
TEST(IndependentData, SpuriousEventsInCorrelatedNoiseDoNotMakeTheEstimateWorse) {
  const std::vector<td::Visit> plan = td::forward_sweep();
  const Truth truth = truth_of(plan);
  const std::vector<double> m = td::position_torques({}, {}, {}, plan);
  int outliers = 0, moving = 0, worse = 0;
  for (int k = 0; k < 40; ++k) {
    const DiagnosisResult r =
        diagnose_residuals(to_table(td::make_table(plan, m, {0.2e-3, 0.8}, 900 + k)));
    for (const Effect& x : r.effects) {
      if (x.name != "outlier") continue;
      ++outliers;
      moving += x.moves_estimate;
    }
    const double eb = vector_error(r.estimate_before, truth), ea = vector_error(r.estimate_after, truth);
    if (ea > eb + 2.0 * r.estimate_after.se_amplitude) {
      ++worse;
      std::printf("  worse (seed %d): %.3f -> %.3f mN*m, SE %.3f; effects:", 900 + k, eb, ea,
                  r.estimate_after.se_amplitude);
      for (const Effect& x : r.effects) std::printf(" %s%s", x.name.c_str(), x.moves_estimate ? "" : "(not moving)");
      std::printf("\n");
    }
  }
  std::printf("AR(1) rho 0.8, one-direction sweep, 40 tables: %d outliers found, %d moving the "
              "estimate; %d estimates worse beyond 2 SE\n",
              outliers, moving, worse);
  EXPECT_EQ(moving, 0);
  EXPECT_EQ(worse, 0);
}

// The true model of a K_T drift, (1 + kappa t)(a sin + c cos + K), fitted by least squares
// (kappa on a grid, then (a, c, K) linear; standard errors from the Jacobian): how often it
// is worse than the plain fit beyond 2 SE, counted as run() does.
int oracle_kt(const std::vector<td::Visit>& plan, const td::TimeEffects& e, int n, std::uint64_t seed0) {
  const Truth truth = truth_of(plan);
  const std::vector<double> m = td::position_torques({}, {}, e, plan);
  int worse = 0;
  double eb = 0, ea = 0;
  for (int k = 0; k < n; ++k) {
    const TorqueTable t = to_table(td::make_table(plan, m, {0.2e-3, 0.0}, seed0 + k));
    const std::size_t N = t.torque.size();
    Eigen::VectorXd y(N);
    for (std::size_t i = 0; i < N; ++i) y(i) = t.torque[i];
    auto fit = [&](double kap, Eigen::MatrixXd& X, Eigen::Vector3d& b) {
      X.resize(N, 3);
      for (std::size_t i = 0; i < N; ++i) {
        const double g = 1.0 + kap * t.time_s[i] / 1000.0;
        X.row(i) << g * std::sin(t.theta_rad[i]), g * std::cos(t.theta_rad[i]), g;
      }
      b = X.colPivHouseholderQr().solve(y);
      return (y - X * b).squaredNorm();
    };
    double best = 1e300, kb = 0.0;
    Eigen::MatrixXd X;
    Eigen::Vector3d b3;
    for (double kap = -0.4; kap <= 0.4; kap += 0.0005) {
      const double r = fit(kap, X, b3);
      if (r < best) best = r, kb = kap;
    }
    fit(kb, X, b3);
    Eigen::MatrixXd J(N, 4);
    J.leftCols(3) = X;
    for (std::size_t i = 0; i < N; ++i)
      J(i, 3) = t.time_s[i] / 1000.0 * (b3(0) * std::sin(t.theta_rad[i]) + b3(1) * std::cos(t.theta_rad[i]) + b3(2));
    const double s2 = best / (static_cast<double>(N) - 4.0);
    const Eigen::MatrixXd cov = s2 * (J.transpose() * J).inverse();
    Eigen::VectorXd b(2);
    b << b3(0), b3(1);
    const SineFitResult f = fit_sine(t.theta_rad, t.torque);
    const double ta = truth.amplitude * std::cos(truth.phase), tc = truth.amplitude * std::sin(truth.phase);
    const double before = std::hypot(f.amplitude * std::cos(f.phase) - ta, f.amplitude * std::sin(f.phase) - tc);
    const double after = std::hypot(b(0) - ta, b(1) - tc);
    const double amp = std::hypot(b(0), b(1));
    const Eigen::Vector2d u(b(0) / amp, b(1) / amp);
    const double se = std::sqrt(u.dot(cov.block<2, 2>(0, 0) * u));
    worse += after > before + 2.0 * se;
    eb += before / n, ea += after / n;
  }
  std::printf("  oracle (the true model, K_T drift): worse %d/%d; mean error %.3f -> %.3f mN*m\n",
              worse, n, eb, ea);
  return worse;
}

// "Never worse" over 100 noise realisations per scenario on the one-direction sweep, where time
// follows angle and every time shape trades off with the unbalance (about 10 s).
TEST(IndependentData, NeverWorseOverAHundredRealisations) {
  const td::TableNoise white{0.2e-3, 0.0};
  td::TimeEffects kt;
  kt.kt_rate = -0.06 / 2160.0;
  // Before the time-shape window: 7 of these 100 worse beyond 2 SE (read as a step or a
  // linear drift, 4-7 SE the wrong way).
  const Tally k = run(td::forward_sweep(), {}, kt, white, 100, 5000, "kt_drift");
  EXPECT_EQ(k.worse, 0);
  EXPECT_GE(k.found, 85);
  // The criterion can be met on this plan: the true model (4 parameters) is never worse.
  EXPECT_EQ(oracle_kt(td::forward_sweep(), kt, 100, 5000), 0);
  td::TimeEffects st;
  st.step = 1.6e-3, st.step_time = 18 * 60.0 - 1.0;
  const Tally s = run(td::forward_sweep(), {}, st, white, 100, 5200, "step");
  EXPECT_EQ(s.worse, 0);
  EXPECT_GE(s.found, 95);
  EXPECT_LT(s.err_after, 0.2 * s.err_before);
  td::TimeEffects ex;
  ex.settle = 1.5e-3, ex.settle_tau = 240.0;
  const Tally x = run(td::forward_sweep(), {}, ex, white, 100, 5400, "exponential_drift");
  EXPECT_EQ(x.worse, 0);
  // Round 3: a settling that moves the estimate beyond 2 SE must also hold with AR(1) errors
  // allowed (residual_guard.h); in about a third of these tables it does not, and the estimate
  // keeps the plain value for it (mean error 0.13 -> 0.21 of 0.32 mN*m before the diagnosis).
  EXPECT_LT(x.err_after, 0.7 * x.err_before);
  // AR(1) noise with rho 0.8-0.85 on this plan: a wander fitted as a step 15-35 BIC ahead of
  // every other reading (before round 3: 3 and 5 of 100 worse beyond 2 SE). An effect moving
  // the estimate must now pass its test with AR(1) errors allowed, else the estimate keeps the
  // plain value and the finding names a repeated or reversed sweep (residual_guard.h).
  EXPECT_EQ(run(td::forward_sweep(), {}, {}, {0.2e-3, 0.8}, 100, 5600, "").worse, 0);
  EXPECT_EQ(run(td::forward_sweep(), {}, {}, {0.15e-3, 0.85}, 100, 5800, "").worse, 0);
}

TEST(IndependentData, EffectOutsideTheCandidateListIsFlaggedAsUnexplained) {
  td::Plant p;
  p.higher_harmonic = 0.8e-3;  // 9 cycles per turn: a 9-ball bearing's waviness
  DiagnosisOptions o;
  o.max_harmonic = 6;
  const Tally t = run(td::forward_and_back(), p, {}, {0.2e-3, 0.0}, 20, 700, "", o);
  EXPECT_GE(t.flagged, 18);
  EXPECT_EQ(t.worse, 0);
}

}  // namespace
}  // namespace poise::estimators

// ---- Raw records of one position (16-bit ADC, 21-bit encoder, +-1.27 deg swing) ----

namespace poise::estimators {
namespace {

OscillationRecord to_record(const td::Record& r) {
  OscillationRecord o;
  o.t = r.t, o.current = r.current, o.phi = r.phi;
  return o;
}

OscillationOptions record_options() {
  OscillationOptions o;
  o.kt = 0.05;
  return o;
}

bool listed(const OscillationDiagnosis& d, const std::string& name, const std::string& phrase) {
  for (const auto& [n, why] : d.not_identifiable) {
    if (n == name && why.find(phrase) != std::string::npos) return true;
  }
  return false;
}

TEST(IndependentRecords, CoggingBelowOneCycleOverTheSwingIsNotFittedButReported) {
  // Orders 96, 60, 32 complete 0.68, 0.42, 0.23 cycles over the 2.54 deg swing.
  const std::array<std::pair<int, double>, 3> cases{{{96, 0.4e-3}, {60, 0.2e-3}, {32, 0.03e-3}}};
  for (const auto& [order, amp] : cases) {
    td::Plant p;
    p.cogging = amp, p.cogging_order = order;
    const OscillationDiagnosis d =
        diagnose_oscillation(to_record(td::make_record(p, {}, {}, 30.0, 11)), record_options());
    for (const auto& e : d.effects) {
      EXPECT_NE(e.name, "cogging") << "true order " << order << ", found " << e.order << " p "
                                   << e.p_adjusted << " amp " << e.params[0].value;
    }
    EXPECT_TRUE(listed(d, "cogging", "not identifiable with this swing")) << order;
    EXPECT_TRUE(listed(d, "cogging", "order 20: 18 deg")) << order;
    // The position's torque is not moved by a term the swing cannot identify.
    EXPECT_LT(std::abs(d.torque_after.value - d.torque_before.value), 0.02e-3) << order;
  }
}

TEST(IndependentRecords, CoggingThatCompletesACycleIsFound) {
  td::Plant p;
  p.cogging = 0.3e-3, p.cogging_order = 180;
  const OscillationDiagnosis d =
      diagnose_oscillation(to_record(td::make_record(p, {}, {}, 30.0, 12)), record_options());
  ASSERT_FALSE(d.effects.empty());
  EXPECT_EQ(d.effects[0].name, "cogging");
  EXPECT_NEAR(d.effects[0].order, 180, 2);
  EXPECT_NEAR(d.effects[0].params[0].value, 0.3e-3, 3.0 * d.effects[0].params[0].se + 0.03e-3);
}

TEST(IndependentRecords, CoulombAsymmetryWithAQuantisedEncoderIsAnAliasNotCogging) {
  int cogging = 0, alias = 0;
  for (int k = 0; k < 4; ++k) {
    td::Plant p;
    p.coulomb_plus = 0.3e-3;
    const OscillationDiagnosis d = diagnose_oscillation(
        to_record(td::make_record(p, {}, {}, 30.0 + 40.0 * k, 20 + k)), record_options());
    for (const auto& e : d.effects) cogging += e.name == "cogging";
    alias += listed(d, "coulomb_asymmetry", "unbalance torque's alias");
  }
  EXPECT_EQ(cogging, 0);
  EXPECT_EQ(alias, 4);
}

TEST(IndependentRecords, CleanQuantisedRecordsAreQuiet) {
  int with_effect = 0;
  for (int k = 0; k < 10; ++k) {
    const OscillationDiagnosis d = diagnose_oscillation(
        to_record(td::make_record({}, {}, {}, 36.0 * k, 40 + k)), record_options());
    with_effect += !d.effects.empty();
  }
  EXPECT_LE(with_effect, 2);  // family-wise alpha 0.05; 10 records
}

}  // namespace
}  // namespace poise::estimators
