#include "kinds/balancing_machine/balancing_kind.h"
#include "core/diagnostics.h"

#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "core/format.h"
#include "engine/kind_interface/procedure_kind.h"
#include "kinds/balancing_machine/balancing_model.h"
#include "kinds/balancing_machine/balancing_sections.h"
#include "kinds/balancing_machine/balancing_study.h"

namespace poise::kinds::balancing_machine {
using namespace poise::engine;
namespace {
using nlohmann::json;

// Each warning once per process (a run builds the study more than once: plan, run, report).
void warn_once(const std::vector<std::string>& warnings) {
  for (const auto& w : warnings) diagnostics::warning_once(w);
}

class BalancingMachineKind final : public ProcedureKind {
 public:
  std::string name() const override { return "balancing_machine"; }
  std::string summary() const override {
    return "the spring-plate vertical balancing machine (Wang 2014): every balancing run integrated with CVODE "
           "from rest to steady state, sensors with gain error and noise, synchronous demodulation, closed-form "
           "and influence-coefficient estimates; the separation, U_mar, stability, URR and accuracy experiments "
           "(model: a balancing-machine model, e.g. models/balancing_machine_wang2014.toml)";
  }
  std::unique_ptr<KindSections> read_sections(TomlReader& root, const StudyConfig& cfg) const override {
    return read_balancing_sections(root, cfg);
  }
  std::unique_ptr<ProcedureStudy> make_study(const StudyConfig& cfg, const std::map<std::string, std::string>& o,
                                             std::size_t samples, std::uint64_t seed) const override {
    BalancingModel model = load_balancing_model(cfg.model_path, o);
    if (cfg.fast_model) model.run.response = procedures::BalancingResponse::kSteadyState;
    auto study = std::make_unique<BalancingStudy>(cfg, std::move(model), samples, seed);
    warn_once(study->warnings());
    return study;
  }
  std::string fast_model(const StudyConfig& /*cfg*/) const override {
    return "the exact steady state of the machine's linear equations, sampled with the same gains and noise "
           "draws (solver.response = \"steady_state\"): it leaves out the start transient's remainder after "
           "settling and the integrator's error";
  }
  std::string validate(const StudyConfig& cfg) const override {
    const BalancingModel model = load_balancing_model(cfg.model_path, cfg.overrides);
    const BalancingStudy study(cfg, model, cfg.samples, cfg.seed);
    const json d = study.details({});
    warn_once(study.warnings());
    return fmt::format(
        "{}: valid. Study '{}' ({}) on model '{}': {} unit-scope random inputs, {} design, {} samples, "
        "seed {}; per sample {} experiment(s), {} simulated balancing runs. Machine: {:.3g} and {:.3g} Hz at "
        "{:.4g} r/min, hard-bearing check {}.",
        cfg.file, cfg.name, cfg.kind, model.name, study.input_names().size(), sampling::to_string(cfg.method),
        cfg.samples, cfg.seed, balancing_sections(cfg).experiments.size(), study.runs_per_sample(),
        d["nominal_machine"]["omega_1_Hz"].get<double>(), d["nominal_machine"]["omega_2_Hz"].get<double>(),
        model.run.speed_rpm, d["hard_bearing"]["ok"].get<bool>() ? "passes" : "FAILS");
  }
};

}  // namespace

std::unique_ptr<StudyKind> make_balancing_machine_kind() { return std::make_unique<BalancingMachineKind>(); }

}  // namespace poise::kinds::balancing_machine
