#pragma once
/// The los_obstruction study kind (engine/study_kind.h): the seeker's beam traced through its frames and
/// housing, and the frames' clearance, over the shafting tolerances (runs in one process).
#include <memory>

#include "engine/study_kind.h"

namespace poise::studies {

std::unique_ptr<StudyKind> make_los_obstruction_kind();

}  // namespace poise::studies
