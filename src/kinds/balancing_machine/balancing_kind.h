#pragma once
/// The balancing_machine study kind (engine/study_kind.h), run through the engine's procedure runner
/// (engine/procedure_kind.h).
#include <memory>

#include "engine/study_kind.h"

namespace poise::studies {

std::unique_ptr<StudyKind> make_balancing_machine_kind();

}  // namespace poise::studies
