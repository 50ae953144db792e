#pragma once
/// The platform_balancing study kind (engine/kind_interface/study_kind.h), run through the engine's procedure runner
/// (engine/kind_interface/procedure_kind.h).
#include <memory>

#include "engine/kind_interface/study_kind.h"

namespace poise::kinds::platform_balancing {
using engine::StudyKind;

std::unique_ptr<StudyKind> make_platform_balancing_kind();

}  // namespace poise::kinds::platform_balancing
