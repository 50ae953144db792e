#include "kinds/geometry_mass_properties/geometry_mass_kind.h"

#include "engine/study_kind.h"
#include "kinds/geometry_mass_properties/geometry_mass_runner.h"
#include "geometry_studies/geometry_study.h"

namespace poise::studies {
namespace {

class GeometryMassPropertiesKind final : public StudyKind {
 public:
  std::string name() const override { return "geometry_mass_properties"; }
  std::string summary() const override {
    return "mass, centre of mass and inertia of a part as built (the simulator disk of Yang 2015: hole position, "
           "clump mass, thickness and wedge tolerances) by Embree ray casting, checked against the divergence "
           "theorem; the eccentricity and couple unbalance that follow (model: e.g. models/simulator_disk_yang2015.toml)";
  }
  std::unique_ptr<KindSections> read_sections(TomlReader& root, const StudyConfig&) const override {
    auto s = std::make_unique<GeometrySections>();
    read_geometry_study(root, name(), s->geometry);
    return s;
  }
  std::string validate(const StudyConfig& cfg) const override { return validate_geometry_mass_study(cfg); }
  std::vector<OutputSpec> outputs(const StudyConfig&) const override { return geometry_mass_outputs(); }
  std::string run(const StudyConfig& cfg, const RunOptions& options) const override {
    return run_geometry_mass_study(cfg, options);
  }
  nlohmann::json replay(const StudyConfig& cfg, std::size_t index, const RunOptions& options) const override {
    return replay_geometry_mass_sample(cfg, index, options);
  }
  std::unique_ptr<InputEvaluator> input_evaluator(const StudyConfig& cfg,
                                                  const std::map<std::string, std::string>& model_overrides,
                                                  std::uint64_t) const override {
    return geometry_mass_input_evaluator(cfg, model_overrides);
  }
  bool runs_sweeps() const override { return false; }
  bool streams() const override { return false; }
};

}  // namespace

std::unique_ptr<StudyKind> make_geometry_mass_properties_kind() { return std::make_unique<GeometryMassPropertiesKind>(); }

}  // namespace poise::studies
