#pragma once
/// The sections of a balancing_machine study file (the shared ones are in
/// engine/study_files/study_config.h):
///   [procedure]     plane_1_surface, plane_2_surface (correction planes: testing surfaces),
///                   estimator = "influence" | "closed_form" (what the machine displays),
///                   calibration_mass, calibration_radius (influence-coefficient test masses)
///   [[experiment]]  name (output prefix), type = "separation" | "umar" | "umar_iso" | "stability" |
///                   "urr" | "accuracy" | "calibration", and per type: mass, radius (every type
///                   but calibration), surface, positions, band,
///                   balance_first, variant, piece_unbalance, requirement, plane_2_offset, claim
///                   (see BalancingExperiment)
#include <memory>
#include <string>
#include <vector>

#include "engine/study_files/study_config.h"

namespace poise::kinds::balancing_machine {
using engine::KindSections;
using engine::KindSectionsOf;
using engine::sections_of;
using engine::StudyConfig;
using engine::TomlReader;

/// One experiment of a balancing-machine study (Wang 2014 Sec. 5, ISO 21940-21 tests).
struct BalancingExperiment {
  std::string name;           ///< output prefix
  std::string type;           ///< separation | umar | umar_iso | stability | urr | accuracy | calibration
  double mass = 0.0;          ///< test mass (kg)
  double radius = 0.0;        ///< its radius (m)
  int surface = 0;            ///< stability: surface carrying the test mass
  int positions = 8;          ///< angular positions (holes) used, evenly spaced from 0 deg
  double band = 0.12;         ///< stability: readings within +-band of their mean
  bool balance_first = true;  ///< stability: correct the rotor with the machine first
  /// stability: "wang2014" (the test as the paper prints it) or "poise" (a set-up of Poise's
  /// own, not in the paper): a label the report and outputs carry, nothing else.
  std::string variant = "poise";
  double plane_2_offset = 0.0;  ///< umar_iso: plane 2's test mass angle from plane 1's (rad)
  double claim = 0.0;           ///< umar_iso: claimed U_mar per plane (kg m), the pass band
  double piece_unbalance = 0;   ///< accuracy: plane unbalance of the test piece (kg m), random angles
  double requirement = 0.0;     ///< urr: required reduction ratio (fraction)
};

struct BalancingSections : KindSectionsOf<BalancingSections> {
  int plane_1_surface = 0, plane_2_surface = 0;
  std::string estimator = "influence";
  double calibration_mass = 0.0, calibration_radius = 0.0;
  std::vector<BalancingExperiment> experiments;
};

std::unique_ptr<KindSections> read_balancing_sections(TomlReader& root, const StudyConfig& cfg);

inline const BalancingSections& balancing_sections(const StudyConfig& cfg) {
  return sections_of<BalancingSections>(cfg);
}

}  // namespace poise::kinds::balancing_machine
