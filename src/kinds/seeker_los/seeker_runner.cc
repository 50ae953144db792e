#include "kinds/seeker_los/seeker_runner.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <thread>

#include "core/format.h"
#include "core/units.h"
#include "engine/kind_interface/study_kind.h"
#include "engine/results/result_io.h"
#include "engine/study_files/toml_reader.h"
#include "kinds/seeker_los/seeker_los_sections.h"
#include "kinds/seeker_los/seeker_los_study.h"
#include "sampling/distributed.h"

namespace poise::kinds::seeker_los {
using namespace poise::model_files;
using namespace poise::engine;
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// The study's model with its overrides.
SeekerModel load_model(const StudyConfig& cfg) { return load_seeker_model(cfg.model_path, cfg.overrides); }

}  // namespace

std::string validate_seeker_study(const StudyConfig& cfg) {
  const SeekerModel model = load_model(cfg);
  const SeekerLosSections& sec = seeker_sections(cfg);
  SeekerSampler sampler(model);
  return fmt::format(
      "{}: valid. Study '{}' ({}) on model '{}': {} random inputs, {} design, {} "
      "samples, seed {}, grid {} x {} over yaw [{:g}, {:g}] deg, pitch [{:g}, {:g}] deg, "
      "requirement {}, {} sweep(s).",
      cfg.file, cfg.name, cfg.kind, model.name, sampler.dimension(), sampling::to_string(cfg.method), cfg.samples,
      cfg.seed, sec.yaw_points, sec.pitch_points, model.yaw_min / units::kRadPerDeg, model.yaw_max / units::kRadPerDeg,
      model.pitch_min / units::kRadPerDeg, model.pitch_max / units::kRadPerDeg,
      sec.requirement_text.empty() ? std::string("none stated (the field figures against 1 px)") : sec.requirement_text,
      cfg.sweeps.size());
}

json replay_seeker_sample(const StudyConfig& cfg, std::size_t index, const RunOptions& options) {
  const SeekerModel model = load_model(cfg);
  const std::size_t n = options.samples.value_or(cfg.samples);
  if (index >= n) throw UsageError("sample index " + std::to_string(index) + " is outside 0.." + std::to_string(n - 1));
  SeekerLosStudy study(cfg, model, n, options.seed.value_or(cfg.seed));
  const SampleResult r = study.replay(index);
  json j;
  j["sample"] = index;
  j["status"] = r.ok ? "ok" : "failed";
  if (!r.ok) j["message"] = r.message;
  for (std::size_t k = 0; k < r.inputs.size(); ++k) j["inputs"][study.sampler().columns()[k].name] = r.inputs[k];
  for (std::size_t k = 0; k < kNumSeekerOutputs; ++k) j["outputs"][kSeekerOutputs[k].name] = r.outputs[k];
  if (r.ok) {
    const auto errs = study.grid_errors(index);
    json grid = json::array();
    for (std::size_t ia = 0; ia < study.grid().alpha().size(); ++ia) {
      for (std::size_t ib = 0; ib < study.grid().beta().size(); ++ib) {
        const auto& e = errs[study.grid().index(ia, ib)];
        grid.push_back({{"yaw_deg", study.grid().alpha()[ia] / units::kRadPerDeg},
                        {"pitch_deg", study.grid().beta()[ib] / units::kRadPerDeg},
                        {"total_arcsec", e.total * units::kArcsecPerRad},
                        {"yaw_arcsec", e.yaw * units::kArcsecPerRad},
                        {"pitch_arcsec", e.pitch * units::kArcsecPerRad}});
      }
    }
    j["grid"] = grid;
  }
  return j;
}

}  // namespace poise::kinds::seeker_los
