#pragma once
/// Internal to residual_diagnosis.cc: a term of the final model told as a reported Effect (its
/// parameters with standard errors in the table's units, and the physical causes of its kind).
#include "estimators/residual_diagnosis.h"
#include "estimators/residual_diagnosis_model.h"
#include "estimators/torque_table.h"

namespace poise::estimators::detail {

/// The effect of term t of model m, from the final fit f (standard errors from f.cov, the
/// harmonic's amplitude and phase by the delta method).
Effect to_effect(const Term& t, const Model& m, const LinearFit& f, const TorqueTable& table);

/// The physical causes of a candidate of this name (order: a harmonic's), in words.
const char* causes_of(const std::string& name, int order);

}  // namespace poise::estimators::detail
