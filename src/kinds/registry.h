#pragma once
/// The table of study kinds, generated at configure time (src/kinds/CMakeLists.txt): adding a
/// kind is a folder src/kinds/<kind>/ with a StudyKind (engine/kind_interface/study_kind.h) and a
/// CMakeLists.txt that calls poise_kind(<kind> SOURCES ... FACTORY make_<kind>_kind).
namespace poise::kinds {

/// Registers every study kind with the engine (once; later calls do nothing). The CLI and
/// the tests call it before reading a study.
void register_study_kinds();

}  // namespace poise::kinds
