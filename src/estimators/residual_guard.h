#pragma once
/// Internal to residual_diagnosis.cc: model choice guarded by what it changes ("Guard" in
/// residual_diagnosis.h), and the family and shape each effect is reported under.
///
/// Guard. An effect of the selected model that moves the unbalance estimate must earn it.
/// Its competing explanations, each fitted in its place on the rest of the model, are
///   - every other candidate of the pool (any column effect: a harmonic against a K_T drift or
///     a step on a one-direction sweep is the measured failure) whose model the data do not
///     reject very strongly, BIC(reading) - BIC(selected) < 10 (Kass and Raftery 1995), and
///     that an encompassing test does not separate from the effect (both fitted together, each
///     given the other by its drop-one F test, Bonferroni over a scanned family: separated when
///     the effect holds beyond doubt, p < 1e-4, and the candidate does not hold at alpha;
///     Davidson and MacKinnon 1981);
///   - AR(1) errors in its place, within 10 BIC, or on a one-direction sweep when the effect
///     is time-shaped, trades off with the first harmonic (r >= 0.5) or moves the estimate
///     beyond 2 SE, and fails its own test with AR(1) errors allowed: its drop-one F test in
///     GLS at the REML rho of the model with it and at the upper end of rho's 95 % profile
///     interval (l_R within 1.92 of its maximum), the larger p, Bonferroni over a scanned
///     family, at alpha, or at 1e-4 when r >= 0.7 or it moves the estimate beyond 2 SE (the
///     "identified beyond doubt" level of residual_assessment.h). With the effect in, rho is
///     estimated low when the effect fits a wander of the noise; the effect must hold at every
///     rho the data accept;
///   - no effect, when the effect moves the estimate beyond 2 SE with drop-one p >= 1e-4.
/// When one of them leaves the estimate within 2 SE of the plain value (the fit without the
/// effect; a wander of correlated noise counts as such) while the effect moves it more than
/// 2 SE (standard errors of the selected model along the difference), the estimate keeps the
/// plain value for this effect, its standard errors widened by half the largest distance of
/// the readings from it (so +-2 SE spans every reading), and an ambiguous finding names the
/// readings and the measurement that would separate them (separating_plan). Guarded effects
/// are dropped together (collinear ones move the estimate far when dropped alone). When every
/// competitor moves the estimate away from the plain value too, assess() averages the readings
/// as before.
///
/// Families. Each effect is reported under a family, the name the issue fixes:
///   time_drift  a smooth drift in time: time_drift (shape "linear"), exponential_drift
///               (shape "exponential"), time_drift_quadratic (a curved drift: shape
///               "not identifiable");
///   step        a level shift;      kt_drift  a multiplicative drift of K_T;
///   harmonic, direction_offset, outlier, autocorrelation as named.
/// A time-shaped effect (or a direction offset) is compared with every other time shape and
/// the direction offset on the rest of the model; when another fits within 2 BIC (Kass and
/// Raftery: "not worth more than a bare mention") among the additive time shapes, or within 6
/// ("strong") across families (a direction offset or the multiplicative K_T drift against an
/// additive time effect: corrections of another kind, which the usual plans confound), or the
/// guard kept it out of the estimate, the shape is not identified: the effect is reported as
/// family time_drift, shape "not identifiable", with the competitor and its BIC difference (a
/// direction offset keeps its family and names the competitor).
#include <string>
#include <vector>

#include "estimators/residual_assessment.h"
#include "estimators/residual_diagnosis.h"
#include "estimators/residual_diagnosis_model.h"

namespace poise::estimators::detail {

inline constexpr double kGuardSe = 2.0;  ///< readings further apart than this many SE disagree

struct GuardInputs {
  GuardInputs(const ModelData& data, const CandidatePool& candidates) : d(data), pool(candidates) {}
  const ModelData& d;
  const CandidatePool& pool;
  double alpha = 0.05;
  bool monotone_plan = false;
};

/// What the guard decided, per term of m: allowance NaN when the term earns its move, else
/// the variance (table unit^2) to add to the plain estimate's (AssessmentInputs::guarded);
/// against: the competing reading that keeps the plain value (label "" none), with its
/// candidate's name ("first harmonic" for the reading with no effect).
struct CompetingReading {
  std::string label;
  std::string name;
};
struct GuardResult {
  std::vector<double> allowance;
  std::vector<CompetingReading> against;
};

/// Applies the guard to every column effect of m (res.effects in the order of m.terms, with
/// res.estimate_selected set); the guarded effects' notes and res.ambiguous are filled.
GuardResult guard_estimate(const Model& m, const GuardInputs& in, DiagnosisResult& res);

/// Sets family, shape, shape_delta_bic and alternative of res.effects. A time-shaped effect
/// the guard kept out of the estimate is a time effect of shape "not identifiable", its
/// alternative the competing reading.
void name_families(const Model& m, const ModelData& d, const CandidatePool& pool, const GuardResult& guard,
                   DiagnosisResult& res);

}  // namespace poise::estimators::detail
