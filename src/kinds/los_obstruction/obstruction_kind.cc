#include "kinds/los_obstruction/obstruction_kind.h"

#include "engine/study_kind.h"
#include "kinds/los_obstruction/obstruction_runner.h"
#include "geometry_studies/geometry_study.h"

namespace poise::studies {
namespace {

class LosObstructionKind final : public StudyKind {
 public:
  std::string name() const override { return "los_obstruction"; }
  std::string summary() const override {
    return "the optical beam of a two-axis seeker traced through its frames and housing over the field of regard "
           "(unobstructed share) and the clearance of the moving frames, nominal and over the shafting tolerances "
           "(model: a seeker model with [geometry])";
  }
  std::unique_ptr<KindSections> read_sections(TomlReader& root, const StudyConfig&) const override {
    auto s = std::make_unique<GeometrySections>();
    read_geometry_study(root, name(), s->geometry);
    return s;
  }
  std::string validate(const StudyConfig& cfg) const override { return validate_obstruction_study(cfg); }
  std::vector<OutputSpec> outputs(const StudyConfig&) const override { return obstruction_outputs(); }
  std::string run(const StudyConfig& cfg, const RunOptions& options) const override {
    return run_obstruction_study(cfg, options);
  }
  nlohmann::json replay(const StudyConfig& cfg, std::size_t index, const RunOptions& options) const override {
    return replay_obstruction_sample(cfg, index, options);
  }
  std::unique_ptr<InputEvaluator> input_evaluator(const StudyConfig& cfg,
                                                  const std::map<std::string, std::string>& model_overrides,
                                                  std::uint64_t) const override {
    return obstruction_input_evaluator(cfg, model_overrides);
  }
  bool runs_sweeps() const override { return false; }
  bool streams() const override { return false; }
};

}  // namespace

std::unique_ptr<StudyKind> make_los_obstruction_kind() { return std::make_unique<LosObstructionKind>(); }

}  // namespace poise::studies
