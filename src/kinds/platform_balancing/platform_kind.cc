#include "kinds/platform_balancing/platform_kind.h"
#include "core/diagnostics.h"

#include <algorithm>
#include <thread>
#include "core/format.h"
#include "engine/kind_interface/procedure_kind.h"
#include "engine/run/procedure_runner.h"
#include "kinds/platform_balancing/platform_model.h"
#include "kinds/platform_balancing/platform_shafting.h"
#include "kinds/platform_balancing/platform_study.h"
#include "kinds/platform_balancing/platform_study_config.h"
#include "sampling/distributed.h"

namespace poise::kinds::platform_balancing {
using namespace poise::engine;
namespace {
using nlohmann::json;

class PlatformBalancingKind final : public ProcedureKind {
 public:
  std::string name() const override { return "platform_balancing"; }
  std::string summary() const override {
    return "a three-gimbal seeker platform balanced axis by axis (inner -> middle -> outer and other orders), each "
           "axis measured with the simulated single-axis test, residual torque over the angle range and its LOS "
           "error through the stabilization loops (model: a platform model, e.g. models/platform_three_gimbal.toml)";
  }
  std::unique_ptr<KindSections> read_sections(TomlReader& root, const StudyConfig& cfg) const override {
    return read_platform_sections(root, cfg);
  }
  std::unique_ptr<ProcedureStudy> make_study(const StudyConfig& cfg, const std::map<std::string, std::string>& o,
                                             std::size_t samples, std::uint64_t seed) const override {
    return std::make_unique<PlatformStudy>(cfg, load_platform_model(cfg.model_path, o), samples, seed);
  }
  // The run first computes the shafting LOS line of [platform.shafting] (platform_shafting.h),
  // which every sample combines with its balancing residual.
  std::string run(const StudyConfig& cfg, const RunOptions& options) const override {
    const PlatformModel model = load_platform_model(cfg.model_path, cfg.overrides);
    const int threads = options.threads > 0 ? options.threads : sampling::Cluster::default_threads();
    const PlatformStudySection& ps = platform_sections(cfg).platform;
    if (options.progress && !ps.shafting_study.empty()) {
      diagnostics::progress("poise: shafting LOS line from " + ps.shafting_study + " (" +
                            std::to_string(ps.shafting_samples) + " samples)");
    }
    const ShaftingLos shafting = compute_shafting_los(cfg, threads);
    return run_procedure_study(
        cfg,
        [&](const StudyConfig& c, std::size_t n, std::uint64_t seed) {
          // A sweep's value comes as an override of the model.
          return std::make_unique<PlatformStudy>(
              c, c.overrides == cfg.overrides ? model : load_platform_model(cfg.model_path, c.overrides), n, seed,
              shafting.los_max_arcsec, shafting.pixel_arcsec);
        },
        options, requirements(cfg));
  }
  std::string validate(const StudyConfig& cfg) const override {
    const PlatformModel model = load_platform_model(cfg.model_path, cfg.overrides);
    check_shafting_study(cfg);
    PlatformStudy study(cfg, model, cfg.samples, cfg.seed);
    return fmt::format(
        "{}: valid. Study '{}' ({}) on model '{}': {} unit-scope random inputs, {} design, {} samples, seed "
        "{}; per sample {} test order(s) x 3 axis tests of {} turntable positions.",
        cfg.file, cfg.name, cfg.kind, model.name, study.input_names().size(), sampling::to_string(cfg.method),
        cfg.samples, cfg.seed, platform_sections(cfg).platform.orders.size(),
        platform_sections(cfg).platform.positions);
  }
};

}  // namespace

std::unique_ptr<StudyKind> make_platform_balancing_kind() { return std::make_unique<PlatformBalancingKind>(); }

}  // namespace poise::kinds::platform_balancing
