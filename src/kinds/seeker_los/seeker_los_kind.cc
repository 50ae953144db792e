#include "kinds/seeker_los/seeker_los_kind.h"

#include <span>

#include "engine/kind_interface/procedure_kind.h"
#include "kinds/seeker_los/seeker_clearance.h"
#include "kinds/seeker_los/seeker_input_evaluator.h"
#include "kinds/seeker_los/seeker_los_sections.h"
#include "kinds/seeker_los/seeker_los_study.h"
#include "kinds/seeker_los/seeker_runner.h"
#include "model_files/seeker_model.h"

namespace poise::kinds::seeker_los {
using namespace poise::engine;
using namespace poise::model_files;
namespace {

class SeekerLosKind final : public ProcedureKind {
 public:
  std::string name() const override { return "seeker_los"; }
  std::string summary() const override {
    return "LOS pointing error of a two-axis seeker from its shafting tolerances (bearing run-out, "
           "perpendicularity, optical axis): Monte Carlo of the exact kinematic chain over the field of "
           "regard, contributions, sweeps (model: a seeker model, e.g. models/seeker_two_axis_wang2011.toml)";
  }
  std::unique_ptr<KindSections> read_sections(TomlReader& root, const StudyConfig& cfg) const override {
    return read_seeker_los_sections(root, cfg);
  }
  std::string validate(const StudyConfig& cfg) const override { return validate_seeker_study(cfg); }
  std::vector<OutputSpec> outputs(const StudyConfig& cfg) const override {
    std::vector<OutputSpec> out;
    for (const auto& o : kSeekerOutputs) out.push_back({o.name, o.unit, o.description});
    const SeekerModel model = load_seeker_model(cfg.model_path, cfg.overrides);  // validates the overrides
    if (seeker_sections(cfg).clearance.clearance_output) {
      if (!model.geometry) {
        throw ValidationError(
            {InputError(SourceLocation{cfg.file, 0, 0}, "clearance.output", "true",
                        "a seeker model with a [geometry] section (" + cfg.model_path + " has none)")});
      }
      out.push_back({"min_clearance_mm", "mm", "least clearance of the nominal frames to the housing"});
    }
    return out;
  }
  /// The [[requirement]] tables, and [requirement] los_error as the requirement it stands for:
  /// p99.73 of the greatest LOS error over the field at most the limit, at 95% confidence.
  std::vector<Requirement> requirements(const StudyConfig& cfg) const override {
    std::vector<Requirement> out = cfg.requirements;
    const SeekerLosSections& sec = seeker_sections(cfg);
    if (sec.requirement_shorthand && !sec.requirement_text.empty()) {
      Requirement r;
      r.output = sec.requirement_in_pixels ? "los_max_px" : "los_max_arcsec";
      r.statistic = "p99_73";
      r.at_most = true;
      r.limit_text = sec.requirement_text;
      r.confidence = 0.95;
      r.file = cfg.file;
      r.origin = cfg.file + ": [requirement] los_error = \"" + sec.requirement_text + "\" (read as p99.73 of " +
                 r.output + " at most " + sec.requirement_text + ", 95% confidence)";
      out.push_back(r);
    }
    return out;
  }
  std::string model_kind() const override { return "seeker_two_axis"; }
  /// Plain Monte Carlo (independent samples, so a quantile's order-statistic interval holds)
  /// of the chain over a 13 x 13 grid of the field of regard, as the LOS study does.
  StudyConfig model_study(const std::string& model_path) const override {
    StudyConfig cfg;
    cfg.kind = name();
    cfg.name = "model_monte_carlo";
    cfg.file = model_path;
    cfg.model_path = model_path;
    cfg.method = sampling::SamplingMethod::kMonteCarlo;
    cfg.plots = false;
    auto sections = std::make_unique<SeekerLosSections>();  // a 13 x 13 grid
    sections->requirement = 1.0;                            // 1 px: only the field_ok_fraction output depends on it
    sections->requirement_in_pixels = true;
    sections->requirement_shorthand = false;
    sections->contribution_samples = 0;
    cfg.sections = std::move(sections);
    return cfg;
  }
  std::vector<std::string> model_tolerance_keys(const std::string& model_path) const override {
    std::vector<std::string> keys = load_seeker_model(model_path).tolerance_keys();
    keys.insert(keys.begin(), "load_deformation");  // k', sampled too (SeekerSampler's k_load)
    return keys;
  }
  std::unique_ptr<ProcedureStudy> make_study(const StudyConfig& cfg, const std::map<std::string, std::string>& o,
                                             std::size_t samples, std::uint64_t seed) const override {
    return std::make_unique<SeekerLosStudy>(cfg, load_seeker_model(cfg.model_path, o), samples, seed);
  }
  /// The engine's one path; contributions by default (the seeker's [output] default: 4096).
  std::string run(const StudyConfig& cfg, const RunOptions& options) const override {
    StudyConfig c = cfg;
    c.contribution_samples = seeker_sections(cfg).contribution_samples;
    return ProcedureKind::run(c, options);
  }
  nlohmann::json replay(const StudyConfig& cfg, std::size_t index, const RunOptions& options) const override {
    return replay_seeker_sample(cfg, index, options);
  }
  std::unique_ptr<InputEvaluator> input_evaluator(const StudyConfig& cfg,
                                                  const std::map<std::string, std::string>& model_overrides,
                                                  std::uint64_t) const override {
    auto overrides = cfg.overrides;
    for (const auto& [k, v] : model_overrides) overrides[k] = v;
    return make_seeker_input_evaluator(cfg, load_seeker_model(cfg.model_path, overrides));
  }
  /// The engine's in-memory run, and the nominal clearance as one more output when asked for.
  McResult evaluate(const StudyConfig& cfg, const std::map<std::string, std::string>& model_overrides,
                    std::size_t samples, std::uint64_t seed, int threads) const override {
    const SeekerLosStudy study(cfg, load_seeker_model(cfg.model_path, model_overrides), samples, seed);
    McResult e = evaluate_procedure(study, threads);
    const SeekerClearanceSpec& g = seeker_sections(cfg).clearance;
    if (g.clearance_output) {  // a design constraint: the same for every sample
      const double c = nominal_min_clearance(study.model(), g.clearance_yaw_points, g.clearance_pitch_points);
      e.names.emplace_back("min_clearance_mm");
      e.values.emplace_back(e.values.empty() ? 0 : e.values[0].size(), 1e3 * c);
    }
    return e;
  }
};

}  // namespace

std::unique_ptr<StudyKind> make_seeker_los_kind() { return std::make_unique<SeekerLosKind>(); }

}  // namespace poise::kinds::seeker_los
