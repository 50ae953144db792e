#pragma once
/// The geometry_mass_properties study kind (engine/kind_interface/study_kind.h): a part as built, its mass properties
/// by ray casting and the divergence theorem, sampled over its making tolerances
/// (engine/kind_interface/procedure_kind.h).
#include <memory>

#include "engine/kind_interface/study_kind.h"

namespace poise::kinds::geometry_mass_properties {
using engine::StudyKind;

std::unique_ptr<StudyKind> make_geometry_mass_properties_kind();

}  // namespace poise::kinds::geometry_mass_properties
