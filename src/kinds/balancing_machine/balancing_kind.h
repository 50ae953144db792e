#pragma once
/// The balancing_machine study kind (engine/kind_interface/study_kind.h), run through the engine's procedure runner
/// (engine/kind_interface/procedure_kind.h).
#include <memory>

#include "engine/kind_interface/study_kind.h"

namespace poise::kinds::balancing_machine {
using engine::StudyKind;

std::unique_ptr<StudyKind> make_balancing_machine_kind();

}  // namespace poise::kinds::balancing_machine
