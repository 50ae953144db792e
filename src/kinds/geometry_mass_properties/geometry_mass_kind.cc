#include "kinds/geometry_mass_properties/geometry_mass_kind.h"

#include "engine/kind_interface/procedure_kind.h"
#include "kinds/geometry_mass_properties/geometry_mass_study.h"
#include "kinds/geometry_mass_properties/mass_properties_sections.h"

namespace poise::kinds::geometry_mass_properties {
using namespace poise::engine;
namespace {

class GeometryMassPropertiesKind final : public ProcedureKind {
 public:
  std::string name() const override { return "geometry_mass_properties"; }
  std::string summary() const override {
    return "mass, centre of mass and inertia of a part as built (the simulator disk of Yang 2015: hole position, "
           "clump mass, thickness and wedge tolerances) by Embree ray casting, checked against the divergence "
           "theorem; the eccentricity and couple unbalance that follow (model: e.g. "
           "models/simulator_disk_yang2015.toml)";
  }
  std::unique_ptr<KindSections> read_sections(TomlReader& root, const StudyConfig&) const override {
    return read_mass_properties_sections(root);
  }
  std::string validate(const StudyConfig& cfg) const override { return validate_geometry_mass_study(cfg); }
  std::unique_ptr<ProcedureStudy> make_study(const StudyConfig& cfg, const std::map<std::string, std::string>& o,
                                             std::size_t samples, std::uint64_t seed) const override {
    return make_geometry_mass_study(cfg, o, samples, seed);
  }
};

}  // namespace

std::unique_ptr<StudyKind> make_geometry_mass_properties_kind() {
  return std::make_unique<GeometryMassPropertiesKind>();
}

}  // namespace poise::kinds::geometry_mass_properties
