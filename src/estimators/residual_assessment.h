#pragma once
/// Internal to residual_diagnosis.cc: what the selected model can and cannot tell apart, and
/// which of its effects the reported unbalance estimate takes ("Identifiability" and "Never
/// worse" in residual_diagnosis.h).
///
/// Canonical correlation r(A, B) of two column sets: the largest singular value of
/// Q_A^T Q_B (Q: orthonormal bases); r = 1 when a combination of one lies in the span of the
/// other. Variance inflation of a candidate against the base: 1 / (1 - r^2) with B the base
/// columns. Limits: kConfounded = 0.9 (VIF 5.3), the usual "serious collinearity" line; a
/// pair with r >= 0.5 whose BICs differ by less than 2 is also ambiguous: the data then do
/// not prefer either (Kass and Raftery 1995: |delta BIC| < 2 is "not worth more than a bare
/// mention"). A time-shaped effect (step, drift, settling, K_T drift) that trades off with
/// the first harmonic (r >= 0.5) has every other time shape within kBicVeryStrong = 10 ("very
/// strong" evidence) as a reading; the estimate then averages the readings with equal
/// weights, their spread added to its uncertainty.
#include <functional>
#include <string>
#include <vector>

#include "estimators/residual_diagnosis.h"
#include "estimators/residual_diagnosis_model.h"

namespace poise::estimators::detail {

inline constexpr double kConfounded = 0.9;
inline constexpr double kWeakCorrelation = 0.5;
inline constexpr double kBicIndistinct = 2.0;
inline constexpr double kBicStrong = 6.0;
inline constexpr double kBicVeryStrong = 10.0;
/// An effect that trades off with the first harmonic (r >= kFirstHarmonicLimit, VIF of the
/// first harmonic >= 2) moves the estimate only when its own drop-one test has p below
/// kIdentifiedP: the data identify it beyond doubt.
inline constexpr double kFirstHarmonicLimit = 0.7;
inline constexpr double kIdentifiedP = 1e-4;

/// Column candidates (families: their best member) that could be added to a model.
using CandidatePool = std::function<std::vector<Term>(const Model&)>;

/// "step before row 7", "exponential_drift (tau 240)", "outlier at row 3", or the term's label.
std::string term_label(const Term& t);

/// Largest canonical correlation of the column sets a and b (0 when either is empty or zero;
/// residual_collinearity.cc with residualize and plan_collinearity).
double canonical_correlation(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

/// c minus its least-squares projection on the columns of x.
Eigen::MatrixXd residualize(const Eigen::MatrixXd& c, const Eigen::MatrixXd& x);

/// BIC = -2 ln L + k ln n (ML form), k = columns + AR + scanned parameters.
double model_bic(const Model& m, const ModelData& d);

/// m with term t added (AR(1) refitted when the model has it).
Model with_term(const Model& m, const ModelData& d, Term t);

/// Drop-one F test p of term i in m (OLS, or GLS at m's rho).
double drop_one_p(const Model& m, const ModelData& d, std::size_t i);

/// The model without its term i (columns removed, later terms' first shifted; AR(1) kept).
Model without_term(const Model& m, std::size_t i);

/// First harmonic and constant of the model's fit.
UnbalanceEstimate estimate_of(const Model& m, const ModelData& d);

/// Collinearity of each candidate of the pool (given the base model) with the base and with
/// each other.
std::vector<CandidateCollinearity> plan_collinearity(const Model& base, const ModelData& d, const CandidatePool& pool);

struct AssessmentInputs {
  AssessmentInputs(const ModelData& data, const CandidatePool& candidates) : d(data), pool(candidates) {}
  const ModelData& d;
  const CandidatePool& pool;
  bool monotone_plan = false;        ///< time order follows angle order
  bool residual_correlated = false;  ///< the omnibus whiteness tests fail
  /// The final model of the other search (AR(1) first or deferred) when it ended elsewhere.
  const Model* other_search = nullptr;
  std::string selected_summary, other_summary;  ///< their effects, e.g. "step", "autocorrelation"
  /// Per term: NaN, or the variance to add when the guard keeps the plain estimate for it
  /// (residual_guard.h); nullptr = no guard.
  const std::vector<double>* guarded = nullptr;
};

/// Fills shift_se, r_first_harmonic, moves_estimate, estimate_note of res.effects (in the
/// order of m.terms), res.ambiguous and res.estimate_after.
void assess(const Model& m, const AssessmentInputs& in, DiagnosisResult& res);

/// A plan that would separate candidates named a and b (residual_guard.cc).
std::string separating_plan(const std::string& a, const std::string& b);

/// Time-shaped candidates: drift, quadratic drift, settling, step, K_T drift, AR(1) errors.
bool is_time_like(const std::string& name);

}  // namespace poise::estimators::detail
