#pragma once
/// The los_obstruction study kind (engine/kind_interface/study_kind.h): the seeker's beam traced through its frames and
/// housing, and the frames' clearance, over the shafting tolerances (runs in one process).
#include <memory>

#include "engine/kind_interface/study_kind.h"

namespace poise::kinds::los_obstruction {
using engine::StudyKind;

std::unique_ptr<StudyKind> make_los_obstruction_kind();

}  // namespace poise::kinds::los_obstruction
