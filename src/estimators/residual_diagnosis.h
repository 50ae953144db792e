#pragma once
/// Turntable-level residual diagnosis of a static unbalance measurement: which effects beyond
/// the Eq. 22 model M = MT_s sin(theta + b) + MK (Yang et al. 2015) does the data hold, and
/// what do they do to the unbalance estimate.
///
/// Base model: the linear least-squares model y = X beta + e with X = [sin theta, cos theta, 1]
/// (estimators::fit_sine). Candidate effects, each adding columns to X (or, for
/// autocorrelation, changing the error model):
///
///   harmonic k (k = 2..K)   sin k theta, cos k theta          amplitude, phase_deg
///   time_drift              t - mean(t)                       slope (per s or per measurement)
///   time_drift_quadratic    (t - mean(t))^2, only after time_drift      curvature
///   direction_offset        sweep (+1 / -1), only if both directions occur   half_difference
///   step                    [measured at or after point k], k scanned   level_change, row, time
///   exponential_drift       exp(-(t - t_first) / tau), tau scanned      initial_excess, tau
///   kt_drift                (t - mean t) M(theta) of the current model  relative_rate
///   outlier                 indicator of one point             offset (index, file line)
///   autocorrelation         AR(1) errors in measurement order   rho (restricted LR test,
///                           one-sided: rho > 0, the correlation drifts, thermal lag and a
///                           servo's slow error give successive readings)
/// (families step and exponential_drift, their scans and the K_T drift: residual_candidates.h)
///
/// Why harmonic 2 is not an axis tilt. With the turntable at theta, gravity in the turntable
/// frame is g_T(theta) = g (cos theta u + sin theta v) + g_w w for fixed unit vectors u, v, w
/// (g_w != 0 when the turntable axis is not horizontal). The unbalance torque about the gimbal
/// axis a is m (r x g_T(theta)) . a = m (a x r) . g_T(theta) with r the fixed centre of mass:
/// linear in g_T, so a sin theta + c cos theta + constant for ANY direction of a: a tilt of
/// the gimbal axis against the turntable axis changes a, c and the constant only. A 2nd
/// harmonic needs a term quadratic in g_T(theta): a centre of mass that moves with the load,
/// r(theta) = r0 + C m g_T(theta) (anisotropic elastic sag of the rotor or frame, C not a
/// multiple of the identity: m^2 (a x C g_T) . g_T holds cos^2, sin^2, sin cos = 2nd harmonic),
/// an out-of-round bearing whose contact point shifts with the load direction (friction
/// and run-out torques following the load at twice per turn for an oval race), or a sensor
/// reading T + q T^2 with T = A sin(theta + b) + K (q A^2 / 2 cos(2 theta + 2 b)). These are
/// the causes reported for it.
///
/// t is time_s when the table has it, else the row number (measurement order = row order);
/// the measurement order is the rows sorted by t. K = min(max_harmonic, floor((n - 6) / 2)),
/// so that the base model plus harmonics 2..K keeps >= 5 residual degrees of freedom; any
/// candidate that would leave fewer than 5, or whose columns are (numerically) in the span of
/// the model's, is not examined.
///
/// Statistics. Nested-model F test for adding q columns:
///     F = ((RSS0 - RSS1) / q) / (RSS1 / dof1),   p = P(F(q, dof1) > F),
///     dof1 = n - p1 (one less with AR),          delta_BIC = n ln(RSS1 / RSS0) + q ln n.
/// Outlier: the n indicators are one family. For each point the F test of its indicator is the
/// square of its externally studentized residual t_i (dof n - p - 1); the family's p is the
/// Bonferroni-adjusted min(1, m * p_min) of the largest |t_i| (m points examined), its delta_BIC
/// that of the same point with q = 1.
/// Autocorrelation: e_t = rho e_{t-1} + u_t in measurement order, fitted by Prais-Winsten GLS
/// (residual_diagnosis_model.h) with rho from the restricted (REML) profile likelihood l_R.
/// Test: likelihood ratio LR = 2 (l_R(rho) - l_R(0)) ~ chi^2(1) against OLS,
/// delta_BIC = -LR + ln n, se(rho) from the curvature of l_R. (Over 20000 white-noise
/// records of 36 points the ML version of this LR rejected 1.07 % at the nominal 0.56 % and
/// 7.8 % at 5 %; the REML one 0.40 % and 4.5 %.) Once AR is in the model every fit
/// is GLS and RSS is the transformed RSS; a column candidate is tested with both models fitted
/// at the rho of the larger one, so a smooth effect is not judged against errors whose rho
/// already absorbed it.
///
/// Selection: forward stepwise. In each round every candidate not yet in the model gets its p
/// and delta_BIC; the round's p are adjusted with Holm (step-down; the outlier family counts
/// as one); of those with adjusted p < alpha AND delta_BIC < 0 the one with the smallest
/// adjusted p is added and the model refitted; the search stops when none qualifies.
/// Two refinements, both because AR(1) errors with rho near 1 mimic any smooth missing term
/// (a 2nd harmonic of 0.6 plus a drift of 1.5 over a 36-point sweep, noise 0.2, simulated
/// 400 times: both found in 20 % of the records with the first refinement alone, AR(1) taking
/// the rest; in 98.5 % with both):
///   - after each column is added, AR(1) is tested again given the columns, and removed (with
///     a note) when it no longer qualifies at alpha;
///   - the search is run twice, with AR(1) allowed in any round and with AR(1) deferred until
///     no column candidate qualifies; when they end in different models the one with the lower
///     BIC = -2 ln L + k ln n (ML form, k = columns + 1 with AR) is kept, with a note.
/// When the search stops with AR(1)'s own test at p < alpha but its Holm-adjusted p not, a note
/// says that correlated noise is suggested, not established, that no correction is applied, and
/// which plan would separate it (on a one-direction sweep: the same positions swept the other
/// way or in random order). On the independent generator's AR(1) tables (rho 0.8 and 0.85, 100
/// each) AR(1) is found or suggested in 64 and 61 (55 and 51 with the test two-sided;
/// diagnosis_round3_test); on white noise the
/// note comes at about the rate alpha allows.
/// Holm keeps the chance of adding anything to a clean record <= alpha: whatever either search
/// adds first must pass the same first-round Holm family (exact F tests under independent
/// Gaussian errors, conservative Bonferroni for outliers, REML LR slightly conservative).
/// Measured (with the step, settling and K_T drift candidates): 13 of 400 white-noise records
/// (3.25 %) of 36 points with time_s and an alternating sweep got an effect at alpha = 0.05
/// (tests/estimators/residual_diagnosis_test.cc); on the independent generator's clean tables 29 of 800
/// (3.6 %) over four plans (tests/estimators/independent_data_diagnosis_test.cc).
///
/// Time shapes. After the search, the time-shaped effects it added (drift, quadratic drift,
/// step, exponential settling, K_T drift) are compared as a group with each single shape
/// alone; the lowest BIC is kept (a scanned tau or change point counted as a parameter).
///
/// Identifiability (residual_assessment.h). Before testing, each candidate's canonical
/// correlation with (sin, cos) and its variance inflation against (sin, cos, 1), and its
/// largest canonical correlation with every other candidate (base projected out), are computed
/// under this data's plan (angle order, time order, sweep). After selection, every effect is
/// compared with every candidate on the rest of the model: those with canonical correlation
/// >= 0.9 (VIF >= 5.3) and BIC within 6, or correlation >= 0.5 and BIC within 2, are reported
/// together as one ambiguous finding with the unbalance under each reading and a plan that
/// would separate them. A time-shaped effect that trades off with the unbalance (r >= 0.5)
/// has AR(1) errors as a reading when their BIC is within 6. On a plan where time follows
/// angle, AR(1) errors are always a reading of the harmonics found, and when the search with
/// AR(1) allowed first and the one with AR(1) deferred end in different models, both are
/// readings of equal weight: the plan cannot check the AR(1) form on which the choice rests.
/// An effect whose columns trade off with the first harmonic (canonical correlation >= 0.7
/// given the rest: the first harmonic's variance at least doubled) is identified only when
/// its drop-one p < 1e-4; otherwise "no effect" is a reading and the estimate does not take
/// the effect (the readings' spread goes into its uncertainty).
///
/// Never worse. For each effect, shift_se = how far (a, c) moves when it is dropped from the
/// selected model, in the selected model's standard errors along the move. estimate_after is
/// estimate_selected except: an ambiguous finding contributes the average of its readings
/// with BIC weights exp(-delta_BIC / 2) (Bayesian model averaging, Raftery 1995; equal weights
/// for the two searches' models above, and for the time shapes within 10 BIC of a time-shaped
/// effect that trades off with the first harmonic), the between-readings variance added to
/// the standard errors; except that when the effect itself moves the estimate by less than 1 SE
/// and a reading it is ambiguous with would move it by more than 2 SE, the estimate keeps the
/// value without the effect, its SE widened by half the readings' largest distance from it
/// (only the reading the data do not favour argues for the move; averaging moved the estimate
/// toward it: a 2nd harmonic from sag read also as a step or K_T drift, round-3 battery mean
/// error 0.065 -> 0.076 mN*m, now 0.065; a linear drift on the third generator's seed 11 made
/// worse, 0.062 -> 0.101 mN*m, now kept); an outlier in correlated noise (AR(1) in the model or
/// the whiteness tests failing) does not move the estimate. (Contributions of several findings are added, a first-order
/// approximation.) With a K_T drift the estimate is referred to the first measurement, where
/// K_T is the calibrated (cold) one.
///
/// Guard (residual_guard.h), applied before the above: an effect that moves the estimate must
/// earn it. Its competing explanations fitted in its place (any other candidate within 10 BIC
/// that an encompassing F test does not separate from it; AR(1) errors within 10 BIC or, on a
/// one-direction sweep, when the effect's own test fails with AR(1) errors allowed; "no
/// effect" when it moves the estimate beyond 2 SE with drop-one p >= 1e-4) are compared; when
/// one leaves the estimate within 2 SE of the plain fit (without the effect) while the effect
/// moves it beyond 2 SE, the estimate keeps the plain value for the effect (guarded effects
/// dropped together), its SE widened by half the readings' largest distance from it, and an
/// ambiguous finding names the readings and the measurement that would separate them (reverse,
/// repeat or shuffle the sweep; a second load). Measured: a 2nd harmonic from anisotropic sag
/// taken as a step, 0.028 -> 0.346 mN*m (7 SE worse), now kept at 0.028; AR(1) noise of rho
/// 0.8-0.85 on a one-direction sweep, 3 and 5 of 100 worse beyond 2 SE before, 0 and 0 now
/// (tests/estimators/diagnosis_round3_test.cc).
///
/// Families (Effect::family, Effect::shape): a smooth drift in time is reported as family
/// time_drift with shape "linear" (name time_drift) or "exponential" (name
/// exponential_drift), a step as step, a multiplicative K_T drift as kt_drift; where another
/// time shape fits within 2 BIC (6 across families: a direction offset, the K_T drift), or
/// the guard kept the effect out of the estimate, as time_drift with shape "not identifiable"
/// ("time effect; shape not identifiable") and the competitor in Effect::alternative.
///
/// Omnibus (residual_omnibus.h): the final residual is tested for structure no effect
/// explains (lack of fit against repeated positions or a declared noise, Ljung-Box and runs in
/// measurement order, CUSUM level-shift scan); a failure is reported as unexplained structure,
/// with where it sits.
///
/// Limits. A K_T scale error or a turntable angle-zero or angle-scale error changes the first
/// harmonic itself and leaves no trace in the residuals: they are listed as not identifiable
/// and need a calibration (known load; angle standard).
///
/// Reported parameters are those of the final model (all effects estimated together), with
/// standard errors from sigma^2 (X^T X)^-1 of the (transformed) final fit and the delta method.
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "estimators/residual_omnibus.h"
#include "estimators/torque_table.h"

namespace poise::estimators {

/// How the diagnosis searches.
struct DiagnosisOptions {
  double alpha = 0.05;          ///< familywise level per round (Holm), in (0, 1)
  int max_harmonic = 6;         ///< highest harmonic tried (>= 1; 1 = none), capped as above
  bool outliers = true;         ///< try the outlier family
  bool autocorrelation = true;  ///< try AR(1) errors
  bool steps = true;            ///< try the step family
  bool exponential = true;      ///< try the exponential settling family
  bool kt_drift = true;         ///< try the multiplicative drift of K_T
  /// Independent noise level (sd of one point, table unit) for the omnibus lack-of-fit test,
  /// e.g. the scatter of the period integrals within a position / sqrt(periods); 0 = none.
  double noise = 0.0;
};

/// The once-per-turn unbalance: amplitude MT_s >= 0, phase b (rad, [0, 2 pi)), offset MK,
/// with standard errors (phase in rad), in the table's torque unit.
struct UnbalanceEstimate {
  double amplitude = 0.0, phase = 0.0, offset = 0.0;
  double se_amplitude = 0.0, se_phase = 0.0, se_offset = 0.0;
};

/// One parameter of an effect, in the final model.
struct EffectParam {
  std::string name;  ///< e.g. "amplitude", "phase_deg", "slope", "rho"
  double value = 0.0;
  double se = 0.0;   ///< standard error
  std::string unit;  ///< e.g. "mN*m", "deg", "mN*m/s"; "" for rho
};

/// An effect added to the model.
struct Effect {
  std::string name;      ///< harmonic, time_drift, time_drift_quadratic, exponential_drift,
                         ///< step, kt_drift, direction_offset, outlier, autocorrelation: the
                         ///< candidate fitted (its family and shape below)
  int order = 0;         ///< harmonic order k (harmonic only; 0 else)
  int index = -1;        ///< outlier: 0-based data row; -1 else
  std::size_t line = 0;  ///< outlier: 1-based file line (from TorqueTable::rows); 0 else
  std::vector<EffectParam> params;
  double p_value = 1.0;     ///< raw p of its round (outlier: Bonferroni over the family)
  double p_adjusted = 1.0;  ///< Holm-adjusted p of its round
  double delta_bic = 0.0;   ///< BIC(with) - BIC(without) in its round; < 0 favours it
  std::string causes;       ///< the physical causes that produce such an effect
  /// How far the first harmonic (a, c) moves when this effect is dropped from the selected
  /// model, in standard errors of the selected model along that move.
  double shift_se = 0.0;
  /// Largest canonical correlation of its columns with sin theta, cos theta given the rest
  /// of the selected model: how much it trades off with the unbalance.
  double r_first_harmonic = 0.0;
  bool moves_estimate = true;  ///< false: estimate_after does not take it (note says why)
  std::string estimate_note;
  /// The family it is reported under (residual_guard.h): time_drift (name time_drift,
  /// time_drift_quadratic or exponential_drift, or any time shape not identified), step,
  /// kt_drift, harmonic, direction_offset, outlier, autocorrelation.
  std::string family;
  /// time_drift only: "linear", "exponential" or "not identifiable"; "" for other families.
  std::string shape;
  /// Time shapes and direction offset: the closest other shape or direction offset on the
  /// rest of the model ("" none examined) and its BIC minus this effect's (< 2: shape not
  /// identified; NaN when none was examined).
  std::string alternative;
  double shape_delta_bic = std::numeric_limits<double>::quiet_NaN();
};

/// Collinearity of one candidate with the base model and the other candidates under this
/// data's plan (angle order, time order, sweep), before any test.
struct CandidateCollinearity {
  std::string candidate;            ///< e.g. "harmonic 3", "time_drift", "step at mid-run"
  double r_first_harmonic = 0.0;    ///< canonical correlation with (sin, cos), constant removed
  double vif_base = 1.0;            ///< 1 / (1 - R^2) against (sin, cos, 1)
  std::string most_collinear_with;  ///< the other candidate it is closest to ("" none)
  double r_other = 0.0;             ///< their canonical correlation, base projected out
};

/// One reading of an ambiguous finding: the selected model with the finding's effect
/// replaced by another candidate (or by nothing).
struct Reading {
  std::string effects;         ///< e.g. "direction_offset", "time_drift", "no effect"
  double delta_bic = 0.0;      ///< BIC(reading) - BIC(selected model)
  UnbalanceEstimate estimate;  ///< the unbalance under this reading
};

/// Candidates the data cannot tell apart, reported together.
struct AmbiguousFinding {
  std::vector<Reading> readings;  ///< the selected one first
  double correlation = 0.0;       ///< largest canonical correlation between them
  std::string why;                ///< what in the plan confounds them
  std::string plan;               ///< a test plan that would separate them
};

/// Result of diagnose_residuals. Torques in the table's unit (TorqueTable::unit).
struct DiagnosisResult {
  std::vector<Effect> effects;        ///< in the order added
  double rmse_before = 0.0;           ///< sqrt(RSS / n) of the base fit
  double rmse_after = 0.0;            ///< sqrt(RSS / n) of the final model (transformed RSS with AR)
  UnbalanceEstimate estimate_before;  ///< fit_sine of the data
  /// The estimate reported (see "Never worse"): estimate_selected unless an effect is ambiguous
  /// or an outlier in correlated noise. With time drift the intercept is at the mean time,
  /// with a direction offset midway between directions, with a K_T drift the first harmonic
  /// and offset are those of the first measurement.
  UnbalanceEstimate estimate_after;
  std::vector<double> fitted_before, residual_before;  ///< per point, base fit
  /// Per point, final model: fitted = X beta (plus, with AR, the one-step prediction
  /// rho e_{t-1}); residual = measured - fitted (with AR the innovation, the first point in
  /// measurement order scaled by sqrt(1 - rho^2)), so that rmse_after = RMS of residual_after.
  std::vector<double> fitted_after, residual_after;
  std::vector<std::string> tested;  ///< each candidate of the last round with p and delta_BIC
  std::vector<std::string> notes;   ///< e.g. AR(1) removed once columns explained it
  int rounds = 0;                   ///< rounds run, the last one adding nothing
  int max_harmonic = 0;             ///< highest harmonic examined after the cap
  /// The unbalance under the whole selected model. estimate_after differs from it where an
  /// effect is ambiguous, trades off with the first harmonic without being identified, or is
  /// an outlier in correlated noise (see "Never worse" above).
  UnbalanceEstimate estimate_selected;
  std::string plan;                                 ///< the plan as the data show it
  std::vector<CandidateCollinearity> collinearity;  ///< every candidate under this plan
  std::vector<AmbiguousFinding> ambiguous;
  OmnibusResult omnibus;  ///< structure left in residual_after
  /// Effects no residual of one test can reveal, with why and what would (candidate, why).
  std::vector<std::pair<std::string, std::string>> not_identifiable;
};

/// Runs the diagnosis (method above) on table.torque (the file's unit) against
/// table.theta_rad, with table.time_s and table.sweep when present. Deterministic.
/// Throws poise::Error for options out of range, inconsistent column sizes, or data that the
/// base fit refuses (see fit_sine).
DiagnosisResult diagnose_residuals(const TorqueTable& table, const DiagnosisOptions& options = {});

/// Error of an unbalance estimate against a known load: estimate - truth.
struct EstimateError {
  double amplitude = 0.0;  ///< amplitude error, torque unit
  double phase_deg = 0.0;  ///< phase error, deg, wrapped to (-180, 180]
  /// |A e^{i b} - A0 e^{i b0}|: the unbalance left after a counterweight placed from the
  /// estimate (Eq. 23), torque unit.
  double vector = 0.0;
};

/// Errors of estimate_before and estimate_after against a known load.
struct KnownLoadErrors {
  EstimateError before, after;
};

/// Errors of the diagnosis' estimates against a known load of true_amplitude (torque unit of
/// the table) at true_phase_rad (the phase b of Eq. 22, e.g. the mass' mounting angle).
KnownLoadErrors known_load_errors(const DiagnosisResult& result, double true_amplitude, double true_phase_rad);

}  // namespace poise::estimators
