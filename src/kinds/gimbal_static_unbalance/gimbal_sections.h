#pragma once
/// The sections of a gimbal_static_unbalance study file (the shared ones are in
/// engine/study_files/study_config.h): the test campaign, as groups of tests.
///   [[group]]       name, positions (turntable positions, evenly spaced from 0),
///                   placement = "sequential" | "interleaved" | "back_and_forth", repeats,
///                   counterweight_placement = "model" | "disk_frame" | "turntable", notes
///   [[group.load]]  mass, radius, angle (a test mass of a loading test)
/// Study keys an override may set (an optimizer's test-plan choice): group.positions,
/// group.placement, group.repeats, group.counterweight_placement (every group) or
/// group.<name>.<key> (one group).
#include <map>
#include <string>
#include <vector>

#include "engine/study_files/study_config.h"

namespace poise::kinds::gimbal_static_unbalance {
using engine::KindSections;
using engine::KindSectionsOf;
using engine::sections_of;
using engine::StudyConfig;
using engine::TomlReader;

/// A test mass of a gimbal loading test (Yang 2015, Tables 2-3).
struct GimbalLoad {
  double mass = 0.0;    ///< kg
  double radius = 0.0;  ///< m
  double angle = 0.0;   ///< rad
};

/// A group of tests of one campaign: the same plan (number of positions), `repeats`
/// runs of each load; statistics (RMSE against the loads) are taken per group.
struct GimbalGroup {
  std::string name;
  std::size_t positions = 36;  ///< evenly spaced over 360 deg, from 0
  /// Order in which the turntable visits them: "sequential" (0, 10, 20, ... deg),
  /// "interleaved" (van der Corput order: 0, 180, 90, 270, ... deg, so that a drift in time
  /// does not follow the angle) or "back_and_forth" (the even positions going up, the odd
  /// ones coming back down, approached from the other side).
  std::string placement = "sequential";
  std::size_t repeats = 1;
  /// How this group's counterweights are placed: "model" (the model's [counterweight]
  /// placement), "disk_frame" or "turntable" (gimbal_model.h), so that one study can set the
  /// two side by side.
  std::string counterweight_placement = "model";
  std::vector<GimbalLoad> loads;
};

struct GimbalSections : KindSectionsOf<GimbalSections> {
  std::vector<GimbalGroup> groups;
};

std::unique_ptr<KindSections> read_gimbal_sections(TomlReader& root, const StudyConfig& cfg);

/// Applies the study keys group[.<name>].positions | placement | repeats; returns the rest.
std::map<std::string, std::string> apply_gimbal_study_overrides(StudyConfig& cfg,
                                                                const std::map<std::string, std::string>& overrides);

inline const GimbalSections& gimbal_sections(const StudyConfig& cfg) { return sections_of<GimbalSections>(cfg); }

}  // namespace poise::kinds::gimbal_static_unbalance
