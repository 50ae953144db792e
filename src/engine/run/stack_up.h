#pragma once
/// Worst case, RSS and Monte Carlo side by side: the figures a tolerance analyst sets beside
/// each other, for a study whose outputs follow from its inputs alone (a closed-form or formula
/// kind: ProcedureStudy::evaluates_inputs, no randomness of its own, input_limits given).
///
/// Per output (summary.json "stack_up", the report's "Worst case, RSS and Monte Carlo"):
///   nominal        the output at every input's mean (an asymmetric deviation's mean is off
///                  the drawn value).
///   sensitivities  c_i = d output / d input_i at the box's centre by central differences
///                  (step 1e-3 of the input's half-width), in output unit per input unit.
///   worst_case     the output's extremes over the box of the drawing's limits [lower_i,
///                  upper_i]: the min and max over its 2^n corners (2^n at most 65536 and at
///                  most the run's samples or 4096), exact for an output monotone in each
///                  input, and its linearised bound f(centre) -+
///                  sum |c_i| h_i (h_i the half-widths) beside it.
///   rss            f(centre) -+ sqrt(sum (c_i h_i)^2): the classic root-sum-square of the
///                  tolerances as written, which reads each h_i as the same number of sigmas;
///                  and the first-order standard deviation sqrt(sum (c_i sd_i)^2) of the
///                  declared distributions.
///   monte_carlo    the run's mean, sd, min, p0.135, p99.865 and max.
///   contributions  each input's share in %: of the worst case (|c_i| h_i / sum), of the RSS
///                  variance ((c_i sd_i)^2 / sum), and of the Monte Carlo variance (the squared
///                  standardized regression coefficients of the run, sampling/cross_moments.h;
///                  with their sum, R^2, which is 1 for a linear output).
///   capability     for an output a [[requirement]] gives specification limits (within):
///                  Cp = (USL - LSL) / (6 s) with its chi-square 95% interval, Cpk with Bissell's,
///                  and parts per million outside from the run with the Clopper-Pearson interval.
#include <nlohmann/json.hpp>

#include "engine/kind_interface/procedure_study.h"
#include "engine/results/requirements.h"

namespace poise::engine {

/// The stack-up figures of a finished run, or null when the study has no input box (or its
/// centre has no value).
nlohmann::json stack_up_json(const ProcedureStudy& study, const McResult& mc,
                             const std::vector<Requirement>& requirements);

/// The report's section of those figures ("" for null).
std::string stack_up_html(const nlohmann::json& stack_up);

}  // namespace poise::engine
