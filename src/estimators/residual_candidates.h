#pragma once
/// Internal to residual_diagnosis.cc: the candidates that are families scanned over a
/// parameter, and the multiplicative drift of the torque constant (statistics in
/// residual_diagnosis.h).
///
///   step               [k-th point in measurement order or later], k = 3 .. n - 3: a level
///                      shift (re-zeroed amplifier, a knock that moved a lead). Family over k,
///                      Bonferroni over the change points examined.
///   exponential_drift  exp(-(t - t_first) / tau), tau on 12 log-spaced values from 1/30 of
///                      the span to the span (longer ones are a linear drift): thermal settling
///                      of the motor, amplifier or bearing grease. Family over tau, Bonferroni.
///   kt_drift           (t - mean t) (a sin theta + c cos theta + K) with a, c, K of the
///                      current model: the torque constant changing in time (motor heating,
///                      K_T falls about 0.1 %/K for NdFeB magnets) scales the whole measured
///                      torque, M_meas = (1 + kappa (t - mean t)) M(theta). One Gauss-Newton
///                      step of the product model about kappa = 0; its coefficient is kappa.
#include <functional>
#include <string>
#include <vector>

#include "estimators/residual_diagnosis_model.h"

namespace poise::estimators::detail {

/// Best change point of the step family, Bonferroni-adjusted; index = first row after it.
Term step_family(const Model& m, const ModelData& d);

/// Best time constant of the exponential family (t: time from its mean), Bonferroni-adjusted.
Term exponential_family(const Model& m, const ModelData& d, const std::vector<double>& t);

/// The K_T drift column given the current model's first harmonic and constant.
Term kt_drift_term(const Model& m, const ModelData& d, const std::vector<double>& t);

/// Backward elimination after the forward search: an effect whose removal lowers the BIC of
/// the final model (AR(1) refitted) is dropped, with a note.
void drop_redundant(const ModelData& d, Model& m, std::vector<std::string>& notes);

/// The time-shaped effects of m (drift, quadratic drift, step, settling, K_T drift) against
/// each single time shape of the pool on the rest of the model; the lowest BIC is kept.
void compare_time_shapes(const ModelData& d, const std::function<std::vector<Term>(const Model&)>& pool, Model& m,
                         std::vector<std::string>& notes);

/// Column of a step at position k of the measurement order.
Eigen::MatrixXd step_column(const ModelData& d, std::size_t k);

/// Column of an exponential settling with time constant tau.
Eigen::MatrixXd exponential_column(const std::vector<double>& t, double tau);

/// The time constants scanned (time unit of t).
std::vector<double> exponential_taus(const std::vector<double>& t);

}  // namespace poise::estimators::detail
