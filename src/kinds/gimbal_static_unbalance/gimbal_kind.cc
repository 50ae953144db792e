#include "kinds/gimbal_static_unbalance/gimbal_kind.h"

#include "core/format.h"
#include "engine/kind_interface/procedure_kind.h"
#include "kinds/gimbal_static_unbalance/gimbal_measured_effects.h"
#include "kinds/gimbal_static_unbalance/gimbal_sections.h"
#include "kinds/gimbal_static_unbalance/gimbal_study.h"
#include "model_files/gimbal_model.h"

namespace poise::kinds::gimbal_static_unbalance {
using namespace poise::engine;
using namespace poise::model_files;
namespace {

class GimbalStaticUnbalanceKind final : public ProcedureKind {
 public:
  std::string name() const override { return "gimbal_static_unbalance"; }
  std::string summary() const override {
    return "the static-unbalance test of a gimbal axis on a turntable simulated end to end (disk rotor's "
           "Lagrange equations with CVODE, servo-driven oscillation at each position, current integration, "
           "sine fit, counterweight) over the rig's tolerances (model: a gimbal model, e.g. "
           "models/gimbal_simulator_yang2015.toml)";
  }
  std::unique_ptr<KindSections> read_sections(TomlReader& root, const StudyConfig& cfg) const override {
    return read_gimbal_sections(root, cfg);
  }
  std::map<std::string, std::string> apply_study_overrides(
      StudyConfig& cfg, const std::map<std::string, std::string>& overrides) const override {
    return apply_gimbal_study_overrides(cfg, overrides);
  }
  std::unique_ptr<ProcedureStudy> make_study(const StudyConfig& cfg, const std::map<std::string, std::string>& o,
                                             std::size_t samples, std::uint64_t seed) const override {
    GimbalModel model = load_gimbal_model(cfg.model_path, o);
    if (cfg.fast_model) {
      model.plan.position_model = procedures::PositionModel::kPeriodMean;
      model.plan.supports = procedures::Supports::kQuasiStatic;  // for the positions it integrates
    }
    return std::make_unique<GimbalStudy>(cfg, std::move(model), samples, seed);
  }
  std::string fast_model(const StudyConfig& /*cfg*/) const override {
    return "each position's mean current from the rigid rotor's load averaged over whole periods of the "
           "reference (the rotor following it exactly), with the acquisition's errors drawn as in the full "
           "model; positions that would saturate the drive or must be sampled are integrated on "
           "quasi-static supports. It leaves out the tracking error, the start transient's remainder and "
           "the supports' dynamics";
  }
  bool takes_measured_effects() const override { return true; }
  std::optional<EffectsInModel> effects_in_model(const StudyConfig& cfg, const estimators::TorqueTable& table,
                                                 const estimators::DiagnosisResult& result) const override {
    return gimbal_effects_in_model(cfg, outputs(cfg), table, result);
  }
  std::string validate(const StudyConfig& cfg) const override {
    const GimbalModel model = load_gimbal_model(cfg.model_path, cfg.overrides);
    GimbalStudy study(cfg, model, cfg.samples, cfg.seed);
    std::size_t tests = 0, positions = 0;
    for (const auto& g : gimbal_sections(cfg).groups) {
      tests += g.repeats * g.loads.size();
      positions += g.repeats * g.loads.size() * g.positions;
    }
    std::string text = fmt::format(
        "{}: valid. Study '{}' ({}) on model '{}': {} unit-scope random inputs, {} design, {} "
        "samples, seed {}; per sample {} group(s), {} simulated tests, {} turntable positions.",
        cfg.file, cfg.name, cfg.kind, model.name, study.input_names().size(), sampling::to_string(cfg.method),
        cfg.samples, cfg.seed, gimbal_sections(cfg).groups.size(), tests, positions);
    text += " Per-test error mechanism: " + model.error_mechanism + ".";
    const auto warnings = plausibility_warnings(model);
    for (const std::string& w : warnings) text += "\nwarning: " + w + ".";
    if (!warnings.empty()) text += "\n";
    return text;
  }
};

}  // namespace

std::unique_ptr<StudyKind> make_gimbal_static_unbalance_kind() { return std::make_unique<GimbalStaticUnbalanceKind>(); }

}  // namespace poise::kinds::gimbal_static_unbalance
