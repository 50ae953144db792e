#pragma once
/// The geometry_mass_properties study kind (engine/study_kind.h): a part as built, its mass properties by ray casting
/// and the divergence theorem, sampled over its making tolerances (engine/procedure_kind.h).
#include <memory>

#include "engine/study_kind.h"

namespace poise::studies {

std::unique_ptr<StudyKind> make_geometry_mass_properties_kind();

}  // namespace poise::studies
