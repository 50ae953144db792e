#pragma once
/// The seeker_los study kind: the line-of-sight pointing error of a two-axis seeker from its
/// shafting tolerances, a Monte Carlo of the exact kinematic chain over the field of regard
/// (models/seeker_los_chain.h), with contributions, sweeps and an optional declared budget.
#include <memory>

#include "engine/kind_interface/study_kind.h"

namespace poise::kinds::seeker_los {
using engine::StudyKind;

std::unique_ptr<StudyKind> make_seeker_los_kind();

}  // namespace poise::kinds::seeker_los
