#pragma once
#include <map>
#include <memory>
#include <vector>
/// The geometry_mass_properties study: the simulator disk as built (models/simulator_disk_*.toml)
/// sampled from its tolerances; per sample the mesh is generated and its mass properties
/// computed by Embree ray casting and by the divergence theorem (geometry/mass_properties.h),
/// giving the rotor's eccentricity e, its angle and the inertia from geometry rather than from
/// a declared e. Besides the samples: the nominal disk against its closed form, and the ray
/// integration's convergence with ray density (with timings).
///
/// Per-sample outputs (ray cast unless named exact):
///   mass_g, e_um, eps_deg, unbalance_gmm (m e), Jzz_kgm2 (about the centre of mass, disk
///   axis), Jxx_kgm2, Jyy_kgm2, axis_tilt_arcmin (principal axis nearest z against z: the
///   couple unbalance), e_exact_um, e_ray_error_um, mass_ray_error_pct.
#include <nlohmann/json.hpp>
#include <string>

#include "engine/input_evaluation.h"
#include "engine/study_config.h"
#include "engine/study_runner.h"

namespace poise::studies {

struct OutputSpec;
/// The per-sample outputs with units.
std::vector<OutputSpec> geometry_mass_outputs();
/// The study's outputs at given inputs (the disk's deviation columns; engine/input_evaluation.h).
std::unique_ptr<InputEvaluator> geometry_mass_input_evaluator(const StudyConfig& cfg,
                                                               const std::map<std::string, std::string>& model_overrides);

std::string validate_geometry_mass_study(const StudyConfig& cfg);
std::string run_geometry_mass_study(const StudyConfig& cfg, const RunOptions& options);
nlohmann::json replay_geometry_mass_sample(const StudyConfig& cfg, std::size_t index, const RunOptions& options);

}  // namespace poise::studies
