#pragma once
/// The platform_balancing study kind (engine/study_kind.h), run through the engine's procedure runner
/// (engine/procedure_kind.h).
#include <memory>

#include "engine/study_kind.h"

namespace poise::studies {

std::unique_ptr<StudyKind> make_platform_balancing_kind();

}  // namespace poise::studies
