#pragma once
/// The table of study kinds. Adding a kind: a folder src/kinds/<kind>/ with a StudyKind
/// (engine/study_kind.h), its library in src/kinds/CMakeLists.txt, and one line in
/// registry.cc.
namespace poise::studies {

/// Registers every study kind with the engine (once; later calls do nothing). The CLI and
/// the tests call it before reading a study.
void register_study_kinds();

}  // namespace poise::studies
