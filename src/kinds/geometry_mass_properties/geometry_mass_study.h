#pragma once
/// The geometry_mass_properties study: the simulator disk as built (models/simulator_disk_*.toml)
/// sampled from its tolerances; per sample the mesh is generated and its mass properties
/// computed by Embree ray casting and by the divergence theorem (geometry/mass_properties.h),
/// giving the rotor's eccentricity e, its angle and the inertia from geometry rather than from
/// a declared e. The engine runs it as every kind (engine/run/procedure_runner.h); its own
/// summary.json "details" and report sections: the nominal disk against its closed form, and
/// the ray integration's convergence with ray density (with timings).
///
/// Per-sample outputs (ray cast unless named exact):
///   mass_g, e_um, eps_deg, unbalance_gmm (m e), Jzz_kgm2 (about the centre of mass, disk
///   axis), Jxx_kgm2, Jyy_kgm2, axis_tilt_arcmin (principal axis nearest z against z: the
///   couple unbalance), e_exact_um, e_ray_error_um, mass_ray_error_pct.
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "engine/kind_interface/procedure_study.h"
#include "engine/study_files/study_config.h"

namespace poise::kinds::geometry_mass_properties {
using engine::ProcedureStudy;
using engine::StudyConfig;

/// The study of `cfg` on its model with `model_overrides`, `samples` samples from `seed`.
std::unique_ptr<ProcedureStudy> make_geometry_mass_study(const StudyConfig& cfg,
                                                         const std::map<std::string, std::string>& model_overrides,
                                                         std::size_t samples, std::uint64_t seed);
/// Validates the study with its model; a short human summary.
std::string validate_geometry_mass_study(const StudyConfig& cfg);

}  // namespace poise::kinds::geometry_mass_properties
