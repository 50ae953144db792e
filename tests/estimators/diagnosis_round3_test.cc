// Round 3 of the residual diagnosis on data Poise did not make (tests/support/independent_gimbal_data.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "estimators/oscillation_diagnosis.h"
#include "estimators/residual_diagnosis.h"
#include "estimators/sine_fit.h"
#include "diagnosis_scoring.h"
#include "independent_gimbal_data.h"

namespace poise::estimators {
namespace {

namespace td = poise::testdata;
using scoring::to_table;

struct Truth { double amplitude, phase; };

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

// The family an effect is reported under and its shape ("" for families without one). Before
// the families were reported (round 3) the name was the family and a shape was implied by it.
template <class E>
std::string alternative_of(const E& e) {
  if constexpr (requires { e.alternative; }) {
    return e.alternative;
  } else {
    return "";
  }
}

template <class E>
std::pair<std::string, std::string> family_of(const E& e) {
  if constexpr (requires { e.family; e.shape; }) {
    return {e.family, e.shape};
  } else {
    if (e.name == "time_drift") return {"time_drift", "linear"};
    if (e.name == "exponential_drift") return {"time_drift", "exponential"};
    if (e.name == "time_drift_quadratic") return {"time_drift", "not identifiable"};
    return {e.name, ""};
  }
}

std::string summary(const DiagnosisResult& r) {
  std::string s;
  for (const Effect& e : r.effects) {
    const auto [f, shape] = family_of(e);
    s += f + (e.order ? std::to_string(e.order) : "") + (shape.empty() ? "" : "(" + shape + ")") +
         (e.moves_estimate ? "" : "[not moving]") + " ";
  }
  return s.empty() ? "no effect" : s;
}

// Tallies of one scenario over noise realisations: right family found, a wrong family
// reported as identified, estimates worse beyond 2 SE of the reported estimate.
struct Tally {
  int runs = 0, found = 0, wrong = 0, worse = 0, any = 0;
  int correlated_said = 0;  ///< autocorrelation found, or its note "correlated noise is suggested"
  double err_before = 0.0, err_after = 0.0;
};

// accept(e): the effect is the planted one (family and shape as reported); wrong(e): the
// effect is reported as an identified family that is not the planted one.
template <class Accept, class Wrong>
Tally run(const char* name, const std::vector<td::Visit>& plan, const td::Plant& p,
          const td::TimeEffects& te, const td::TableNoise& noise, int n, std::uint64_t seed0,
          Accept accept, Wrong wrong) {
  const Truth truth = truth_of(plan);
  const std::vector<double> m = td::position_torques(p, {}, te, plan);
  Tally t;
  for (int k = 0; k < n; ++k) {
    const DiagnosisResult r = diagnose_residuals(to_table(td::make_table(plan, m, noise, seed0 + k)));
    const double b = vector_error(r.estimate_before, truth), a = vector_error(r.estimate_after, truth);
    bool hit = false, bad = false;
    for (const Effect& e : r.effects) hit |= accept(e), bad |= wrong(e);
    const bool worse = a > b + 2.0 * r.estimate_after.se_amplitude;
    ++t.runs, t.found += hit, t.wrong += bad, t.worse += worse, t.any += !r.effects.empty();
    bool said = false;
    for (const Effect& e : r.effects) said |= e.name == "autocorrelation";
    for (const std::string& note : r.notes) said |= note.find("correlated noise is suggested") != std::string::npos;
    t.correlated_said += said;
    t.err_before += b / n, t.err_after += a / n;
    if (worse || bad) {
      std::printf("    seed %d: %.3f -> %.3f mN*m (SE %.3f)%s%s: %s\n", static_cast<int>(seed0) + k,
                  b, a, r.estimate_after.se_amplitude, worse ? " worse" : "",
                  bad ? " wrong family" : "", summary(r).c_str());
    }
  }
  std::printf("  %-40s found %2d/%d, wrong family %d, worse %d, correlated noise said %d; mean error %.3f -> "
              "%.3f mN*m\n",
              name, t.found, t.runs, t.wrong, t.worse, t.correlated_said, t.err_before, t.err_after);
  return t;
}

bool is_family(const Effect& e, const std::string& f) { return family_of(e).first == f; }

// A time effect reported with an identified shape other than `shape`.
bool other_time_shape(const Effect& e, const std::string& family, const std::string& shape) {
  const auto [f, s] = family_of(e);
  if (f == "time_drift" && s == "not identifiable") return false;
  const bool time_family = f == "time_drift" || f == "step" || f == "kt_drift";
  return time_family && !(f == family && (shape.empty() || s == shape));
}

// A time effect whose shape is not identifiable names the causes of both readings: its own
// and, after "Or, read as", those of the shape it is not told from.
bool causes_name_both_readings(const Effect& e) {
  if (family_of(e).second != "not identifiable") return true;
  for (const char* other : {"time_drift", "exponential_drift", "step", "kt_drift", "direction_offset"}) {
    if (e.alternative.rfind(other, 0) == 0 && e.name != other) {
      return e.causes.find(std::string(" Or, read as ") + other + ": ") != std::string::npos;
    }
  }
  return true;
}

const td::TableNoise kWhite{0.2e-3, 0.0};

// (a) A 2nd harmonic from anisotropic sag on a one-direction sweep, where a step or a K_T
// drift fits it as a time effect that moves the unbalance estimate (before round 3: seed 102
// at phase 4 rad read as a step, 0.028 -> 0.346 mN*m, 7 SE worse; the third generator
// showed the same as a K_T drift, 0.041 -> 0.345).
TEST(DiagnosisRound3, SecondHarmonicFromSagIsNotTakenAsATimeEffect) {
  int worse = 0, found = 0, runs = 0;
  double err_before = 0.0, err_after = 0.0;
  for (double phase : {0.0, 1.0, 2.0, 3.0, 4.0, 5.0}) {
    td::Plant p;
    p.sag_h2 = 0.15e-3, p.sag_h2_phase = phase;
    const Tally t = run("sag 2nd harmonic 0.15 mN*m", td::forward_sweep(), p, {}, kWhite, 6, 100,
                        [](const Effect& e) { return e.name == "harmonic" && e.order == 2; },
                        [](const Effect& e) { return other_time_shape(e, "", ""); });
    worse += t.worse, found += t.found, runs += t.runs;
    err_before += t.err_before / 6.0, err_after += t.err_after / 6.0;
  }
  std::printf("sag 2nd harmonic, one-direction sweep: found %d of %d, worse %d; mean error %.4f -> %.4f mN*m\n",
              found, runs, worse, err_before, err_after);
  EXPECT_EQ(worse, 0);
  // The harmonic hardly moves the estimate (r = 0 with the first harmonic), the step or K_T
  // drift readings it is ambiguous with would: the estimate keeps the plain value (before 28 Nov
  // 2026 it averaged the readings, and the mean error went 0.065 -> 0.076 mN*m).
  EXPECT_LE(err_after, err_before + 1e-3);
  // 0.15 mN*m against 0.2 mN*m of noise over 36 points is near the detection limit: as many
  // found as before round 3 (15 of 36), none lost to the guard.
  EXPECT_GE(found, 15);
}

// (b) Time effects by family: a linear drift as time_drift (linear), not a step; a settling
// as time_drift (exponential) or "shape not identifiable"; a step as step; a K_T drift as
// kt_drift or a time effect of unidentified shape.
TEST(DiagnosisRound3, TimeEffectsAreReportedByFamily) {
  td::TimeEffects lin, ex, st, kt;
  lin.drift = 1.5e-3 / 2160.0;
  ex.settle = 1.5e-3, ex.settle_tau = 240.0;
  st.step = 1.0e-3, st.step_time = 11 * 60.0 - 1.0;
  kt.kt_rate = -0.06 / 2160.0;
  const auto drift = [](const std::string& shape) {
    return [shape](const Effect& e) {
      const auto [f, s] = family_of(e);
      EXPECT_TRUE(causes_name_both_readings(e)) << e.name << " or " << e.alternative << ": " << e.causes;
      return f == "time_drift" && (s == shape || s == "not identifiable");
    };
  };
  int found = 0, wrong = 0, worse = 0, runs = 0;
  const auto add = [&](const Tally& t) { found += t.found, wrong += t.wrong, worse += t.worse, runs += t.runs; };
  for (const auto& [name, plan] : {std::pair{"shuffled", td::shuffled(3)},
                                   std::pair{"forward and back", td::forward_and_back()},
                                   std::pair{"one direction", td::forward_sweep()}}) {
    std::printf("%s:\n", name);
    add(run("linear drift 1.5 mN*m over the run", plan, {}, lin, kWhite, 8, 200, drift("linear"),
            [](const Effect& e) { return other_time_shape(e, "time_drift", "linear"); }));
    add(run("exponential settling 1.5 mN*m, tau 240 s", plan, {}, ex, kWhite, 8, 300,
            drift("exponential"),
            [](const Effect& e) { return other_time_shape(e, "time_drift", "exponential"); }));
    add(run("step 1.0 mN*m before row 11", plan, {}, st, kWhite, 8, 400,
            [](const Effect& e) { return is_family(e, "step") || family_of(e).second == "not identifiable"; },
            [](const Effect& e) { return other_time_shape(e, "step", ""); }));
    add(run("K_T drift -6 % over the run", plan, {}, kt, kWhite, 8, 500,
            [](const Effect& e) { return is_family(e, "kt_drift") || family_of(e).second == "not identifiable"; },
            [](const Effect& e) { return other_time_shape(e, "kt_drift", ""); }));
  }
  std::printf("time effects: found %d of %d, wrong family %d, worse %d\n", found, runs, wrong, worse);
  // Before round 3: 6 wrong families and 1 worse in these 96 (seed 200, forward and back: a
  // linear drift whose curvature is significant by chance, an exponential 8.3 BIC ahead at
  // p = 0.008 given the linear drift, moving the estimate 0.11 mN*m; now the linear reading,
  // not separated beyond doubt, keeps the plain estimate).
  EXPECT_EQ(worse, 0);
  EXPECT_EQ(wrong, 0);
  EXPECT_GE(found, runs * 9 / 10);
}

// (b) A direction offset on a split sweep (0..180 then 0..-170: the direction is a step at the
// turn, and within each half time follows angle) is not reported as a time drift of
// identified shape.
TEST(DiagnosisRound3, DirectionOffsetOnASplitSweepIsNotReportedAsATimeDrift) {
  td::Plant p;
  p.direction_offset = 0.4e-3;
  // Found: reported as a direction offset, or as a time effect of shape not identifiable with
  // the direction offset as its alternative (the split sweep confounds them).
  const Tally t = run("direction offset 0.4 mN*m, split sweep", td::split_sweep(), p, {}, kWhite,
                      20, 240, [](const Effect& e) {
                        return is_family(e, "direction_offset") ||
                               (family_of(e).second == "not identifiable" &&
                                alternative_of(e).find("direction_offset") != std::string::npos);
                      },
                      [](const Effect& e) { return other_time_shape(e, "", ""); });
  EXPECT_EQ(t.wrong, 0);
  EXPECT_EQ(t.worse, 0);
  EXPECT_GE(t.found, 18);
}

// (d) AR(1) noise on a one-direction sweep: no correction the data cannot separate from the
// noise (before round 3: 3 and 5 of 100 worse beyond 2 SE, a wander fitted as a step), and the
// diagnosis says so: AR(1) found, or its note that correlated noise is suggested and which plan
// would separate it (measured 28 Nov 2026: 55 and 51 of 100; 64 and 61 with the AR(1) test
// one-sided, rho > 0; on the white-noise scenarios above the note comes in 0 to 2 of 6 to 20
// tables, as its test at alpha allows).
void correlated_noise(double sigma, double rho, std::uint64_t seed0) {
  const auto none = [](const Effect&) { return false; };
  const Tally t = run("clean, AR(1) noise", td::forward_sweep(), {}, {}, {sigma, rho}, 100, seed0,
                      none, none);
  EXPECT_EQ(t.worse, 0);
  EXPECT_GE(t.correlated_said, 50);
}

TEST(DiagnosisRound3, CorrelatedNoiseRho080IsNeverMadeWorse) { correlated_noise(0.2e-3, 0.8, 5600); }
TEST(DiagnosisRound3, CorrelatedNoiseRho085IsNeverMadeWorse) { correlated_noise(0.15e-3, 0.85, 5800); }
}  // namespace
}  // namespace poise::estimators

// ---- Raw records of one position (16-bit ADC, 21-bit encoder, 1 kHz, two periods) ----

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

// A swing of 2 A T / (2 pi) = 14.6 deg peak to peak at A = 0.8 rad/s, T = 1 s: cogging orders
// from 360 / 14.6 = 25 per turn complete a cycle over it.
td::Servo wide_swing() {
  td::Servo s;
  s.amplitude = 0.8;
  return s;
}

// Matched-filter SNR of a sinusoid of amplitude T (N m) over the whole record in white noise
// of sd K_T * current_noise per sample: T sqrt(n / 2) / sigma.
double matched_filter_snr(double amplitude, std::size_t n) {
  const double sigma = 0.05 * td::Acquisition{}.current_noise;
  return amplitude * std::sqrt(static_cast<double>(n) / 2.0) / sigma;
}

std::string record_summary(const OscillationDiagnosis& d) {
  std::string s;
  for (const auto& e : d.effects) s += e.name + (e.order ? " " + std::to_string(e.order) : "") + "; ";
  return s.empty() ? "no effect" : s;
}

// (c) Cogging of orders 32..551 over a swing that holds a cycle of each, at amplitudes from a
// whole-record matched-filter SNR of 8 up to the 0.03-0.4 mN*m.
TEST(DiagnosisRound3Records, CoggingAcrossOrdersAboveTheSwingLimitIsFound) {
  int found = 0, runs = 0, reported = 0, within_resolution = 0;
  for (int order : {32, 60, 96, 144, 264, 551}) {
    for (double amp : {0.025e-3, 0.03e-3, 0.1e-3, 0.4e-3}) {
      td::Plant p;
      p.cogging = amp, p.cogging_order = order;
      const td::Record rec = td::make_record(p, wide_swing(), {}, 30.0, 1000 + order);
      const OscillationDiagnosis d = diagnose_oscillation(to_record(rec), record_options());
      // Orders closer than a quarter of the resolution 2 pi / swing (6 here) are not told
      // apart at a low SNR: over the swing their cycles differ by less than a quarter.
      bool hit = false;
      for (const auto& e : d.effects) {
        hit |= e.name == "cogging" && std::abs(e.order - order) <= 6;
        if (e.name != "cogging") continue;
        // The stated resolution holds the planted order.
        ++reported, within_resolution += std::abs(e.order - order) <= e.order_resolution;
        EXPECT_GT(e.order_resolution, 0.0);
      }
      ++runs, found += hit;
      if (!hit) {
        std::printf("  missed: order %d, %.3g mN*m (matched-filter SNR %.1f): %s\n", order,
                    amp * 1e3, matched_filter_snr(amp, rec.t.size()), record_summary(d).c_str());
      }
    }
  }
  std::printf("cogging over a 14.6 deg swing: found %d of %d; %d of %d orders reported within their resolution\n",
              found, runs, within_resolution, reported);
  EXPECT_GE(found, runs * 9 / 10);
  EXPECT_EQ(within_resolution, reported);
}

// (c) A current-sensor offset drift of 1 mA over the two-period record (0.5 mA/s).
TEST(DiagnosisRound3Records, OneMilliampOffsetDriftIsFound) {
  int found = 0, runs = 0;
  for (const td::Servo& s : {td::Servo{}, wide_swing()}) {
    for (int k = 0; k < 10; ++k) {
      td::Acquisition a;
      a.offset_drift = 0.5e-3;
      const OscillationDiagnosis d = diagnose_oscillation(
          to_record(td::make_record({}, s, a, 20.0 + 33.0 * k, 2000 + k)), record_options());
      bool hit = false;
      for (const auto& e : d.effects) hit |= e.name == "offset_drift";
      ++runs, found += hit;
      if (!hit) std::printf("  missed offset drift (seed %d): %s\n", 2000 + k, record_summary(d).c_str());
    }
  }
  std::printf("1 mA offset drift: found %d of %d\n", found, runs);
  EXPECT_GE(found, runs * 9 / 10);
}

// (c) Friction asymmetry at one position is the unbalance torque's alias: reported as not
// identifiable, and nothing (no cogging of a high order) invented in its place.
TEST(DiagnosisRound3Records, FrictionAsymmetryIsNotIdentifiableAndNothingIsInvented) {
  int invented = 0, listed = 0, runs = 0;
  for (const td::Servo& s : {td::Servo{}, wide_swing()}) {
    for (int k = 0; k < 6; ++k) {
      td::Plant p;
      p.coulomb_plus = 0.3e-3 + 0.1e-3 * k;
      const OscillationDiagnosis d = diagnose_oscillation(
          to_record(td::make_record(p, s, {}, 30.0 + 40.0 * k, 3000 + k)), record_options());
      invented += !d.effects.empty();
      for (const auto& [name, why] : d.not_identifiable) listed += name == "coulomb_asymmetry";
      ++runs;
      if (!d.effects.empty()) std::printf("  invented (seed %d): %s\n", 3000 + k, record_summary(d).c_str());
    }
  }
  std::printf("friction asymmetry: %d of %d records with an effect invented\n", invented, runs);
  EXPECT_EQ(invented, 0);
  EXPECT_EQ(listed, runs);
}

// (c) Clean records, both swings: an effect in at most about alpha of them.
TEST(DiagnosisRound3Records, CleanRecordsRarelyGetAnEffect) {
  int any = 0, runs = 0;
  for (const td::Servo& s : {td::Servo{}, wide_swing()}) {
    for (int k = 0; k < 20; ++k) {
      const OscillationDiagnosis d = diagnose_oscillation(
          to_record(td::make_record({}, s, {}, 18.0 * k, 4000 + k)), record_options());
      any += !d.effects.empty(), ++runs;
      if (!d.effects.empty()) std::printf("  clean record (seed %d): %s\n", 4000 + k, record_summary(d).c_str());
    }
  }
  std::printf("clean records: an effect in %d of %d\n", any, runs);
  EXPECT_LE(static_cast<double>(any) / runs, 0.05 + 2.0 * std::sqrt(0.05 * 0.95 / runs));
}

}  // namespace
}  // namespace poise::estimators
