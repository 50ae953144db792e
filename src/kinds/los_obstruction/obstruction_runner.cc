#include "kinds/los_obstruction/obstruction_runner.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <span>
#include <utility>

#include "core/units.h"
#include "geometry/obstruction.h"
#include "sampling/design.h"
#include "geometry_studies/geometry_runner_common.h"
#include "engine/report_plot.h"
#include "engine/study_kind.h"
#include "model_files/seeker_geometry.h"
#include "model_files/seeker_model.h"
#include "geometry_studies/geometry_study.h"

namespace poise::studies {
namespace {
using nlohmann::json;
using geometry::SeekerScenes;

constexpr GeometryOutputDef kOutputs[] = {
    {"min_fraction_pct", "%", "least unobstructed share of the beam over the field of regard"},
    {"mean_fraction_pct", "%", "mean unobstructed share of the beam over the grid"},
    {"full_field_pct", "%", "share of grid points where the whole beam passes"},
    {"min_fraction_shift_ppm", "ppm", "least unobstructed share minus the nominal design's"},
    {"min_clearance_mm", "mm", "least clearance of the moving frames over the field (negative: interference)"},
    {"ring_housing_mm", "mm", "yaw ring to housing, least over the field"},
    {"barrel_housing_mm", "mm", "optical barrel to housing, least over the field"},
    {"barrel_ring_mm", "mm", "optical barrel to yaw ring, least over the field"},
    {"clearance_shift_um", "um", "least clearance minus the nominal design's"},
};
constexpr std::size_t kNumOutputs = std::size(kOutputs);

struct FieldResult {
  std::vector<double> fraction;                      // per grid point
  std::vector<SeekerScenes::Clearance> clearance;    // per grid point (empty if not computed)
};

class ObstructionStudy {
 public:
  ObstructionStudy(const StudyConfig& cfg, std::size_t n, std::uint64_t seed)
      : cfg_(cfg), model_(load_seeker_model(cfg.model_path, cfg.overrides)), sampler_(model_),
        design_(make_design(cfg, seed, n, sampler_.dimension())) {
    if (!model_.geometry) {
      throw ValidationError({InputError(SourceLocation{cfg.file, 0, 0}, "study.model", "\"" + cfg.model_path + "\"",
                                        "a seeker model with a [geometry] section (frames and housing)")});
    }
    scenes_ = std::make_unique<SeekerScenes>(*model_.geometry, seeker_scene_meshes(model_),
                                             geometry_sections(cfg).geometry.beam_rays);
    yaw_ = models::linspace(model_.yaw_min, model_.yaw_max, geometry_sections(cfg).geometry.yaw_points);
    pitch_ = models::linspace(model_.pitch_min, model_.pitch_max, geometry_sections(cfg).geometry.pitch_points);
  }

  const SeekerModel& model() const { return model_; }
  const SeekerSampler& sampler() const { return sampler_; }
  const SeekerScenes& scenes() const { return *scenes_; }
  const std::vector<double>& yaw() const { return yaw_; }
  const std::vector<double>& pitch() const { return pitch_; }

  FieldResult field(const models::SeekerErrorState& state, bool with_clearance) const {
    FieldResult r;
    for (double a : yaw_) {
      for (double b : pitch_) {
        const geometry::GimbalPose pose = geometry::seeker_pose(state, a, b);
        r.fraction.push_back(scenes_->trace_beam(pose).fraction());
        if (with_clearance) r.clearance.push_back(scenes_->clearance(pose));
      }
    }
    return r;
  }

  static std::vector<double> outputs(const FieldResult& f) {
    const double fmin = *std::min_element(f.fraction.begin(), f.fraction.end());
    double mean = 0;
    std::size_t full = 0;
    for (double v : f.fraction) mean += v, full += v == 1.0 ? 1 : 0;
    mean /= static_cast<double>(f.fraction.size());
    double rh = INFINITY, bh = INFINITY, br = INFINITY;
    for (const auto& c : f.clearance) rh = std::min(rh, c.ring_housing), bh = std::min(bh, c.barrel_housing), br = std::min(br, c.barrel_ring);
    const double cmin = std::min({rh, bh, br});
    return {100 * fmin, 100 * mean, 100.0 * static_cast<double>(full) / static_cast<double>(f.fraction.size()), 0.0,
            1e3 * cmin, 1e3 * rh, 1e3 * bh, 1e3 * br, 0.0};
  }

  void compute(std::size_t i, const std::vector<double>& nominal, GeometrySample& out) const {
    compute_geometry_sample(i, design_, sampler_.dimension(), kNumOutputs, out,
                            [&](std::span<const double> u, std::vector<double>& inputs) {
      return outputs_of(sampler_.draw(u, inputs), nominal);
    });
  }

  /// The outputs of one error realization, with the shifts from the nominal design's.
  std::vector<double> outputs_of(const models::SeekerErrorState& state, const std::vector<double>& nominal) const {
    std::vector<double> o = outputs(field(state, geometry_sections(cfg_).geometry.clearance_per_sample));
    o[3] = (o[0] - nominal[0]) * 1e4;  // pct -> ppm
    if (geometry_sections(cfg_).geometry.clearance_per_sample) {
      o[8] = (o[4] - nominal[4]) * 1e3;  // mm -> um
    } else {
      for (std::size_t k = 4; k < kNumOutputs; ++k) o[k] = nominal[k];
      o[8] = 0.0;
    }
    return o;
  }

 private:
  const StudyConfig& cfg_;
  SeekerModel model_;
  SeekerSampler sampler_;
  sampling::Design design_;
  std::unique_ptr<SeekerScenes> scenes_;
  std::vector<double> yaw_, pitch_;
};

// At given inputs (the seeker's columns: the error realization itself): the same tracing as
// a drawn sample's. No randomness of its own.
class ObstructionInputEvaluator final : public InputEvaluator {
 public:
  explicit ObstructionInputEvaluator(StudyConfig cfg) : cfg_(std::move(cfg)), study_(cfg_, 1, cfg_.seed) {
    for (const auto& c : study_.sampler().columns()) {
      names_.push_back(c.name);
      factors_.push_back(c.display_factor);
    }
    for (const auto& o : kOutputs) outputs_.push_back({o.name, o.unit, o.description});
    nominal_ = ObstructionStudy::outputs(study_.field(models::SeekerErrorState{}, true));
  }
  const std::vector<std::string>& input_names() const override { return names_; }
  const std::vector<OutputSpec>& outputs() const override { return outputs_; }
  std::vector<double> nominal_inputs() const override { return study_.sampler().nominal(); }
  void evaluate_points(const InputColumns& inputs, double* values, std::size_t begin, std::size_t end,
                       std::vector<std::pair<std::size_t, std::string>>& failures) const override {
    evaluate_each_point(inputs, factors_, names_.size(), kNumOutputs, values, begin, end, failures,
                        [&](std::size_t, std::span<const double> si, std::span<double> y) {
                          const std::vector<double> o = study_.outputs_of(study_.sampler().state_of(si), nominal_);
                          std::copy(o.begin(), o.end(), y.begin());
                        });
  }

 private:
  StudyConfig cfg_;  // before study_, which refers to it
  ObstructionStudy study_;
  std::vector<std::string> names_;
  std::vector<double> factors_, nominal_;
  std::vector<OutputSpec> outputs_;
};

}  // namespace

std::unique_ptr<InputEvaluator> obstruction_input_evaluator(const StudyConfig& cfg,
                                                             const std::map<std::string, std::string>& model_overrides) {
  StudyConfig c = cfg;
  for (const auto& [k, v] : model_overrides) c.overrides[k] = v;
  return std::make_unique<ObstructionInputEvaluator>(std::move(c));
}

std::vector<OutputSpec> obstruction_outputs() {
  std::vector<OutputSpec> out;
  for (const auto& o : kOutputs) out.push_back({o.name, o.unit, o.description});
  return out;
}

std::string validate_obstruction_study(const StudyConfig& cfg) {
  const ObstructionStudy study(cfg, cfg.samples, cfg.seed);
  const auto& g = *study.model().geometry;
  char buf[640];
  std::snprintf(buf, sizeof buf,
                "%s: valid. Study '%s' (%s) on model '%s': spans %g / %g mm, housing radius %g mm, window %g mm; "
                "%zu random inputs, %s design, %zu samples, seed %llu; grid %zu x %zu, %d beam rays, clearance %s.",
                cfg.file.c_str(), cfg.name.c_str(), cfg.kind.c_str(), study.model().name.c_str(), 1e3 * g.yaw_span,
                1e3 * g.pitch_span, 1e3 * g.housing_radius, 1e3 * g.window_radius, study.sampler().dimension(),
                sampling::to_string(cfg.method).c_str(), cfg.samples, static_cast<unsigned long long>(cfg.seed),
                geometry_sections(cfg).geometry.yaw_points, geometry_sections(cfg).geometry.pitch_points, geometry_sections(cfg).geometry.beam_rays,
                geometry_sections(cfg).geometry.clearance_per_sample ? "per sample" : "nominal only");
  return buf;
}

json replay_obstruction_sample(const StudyConfig& cfg, std::size_t index, const RunOptions& options) {
  const ObstructionStudy study(cfg, geometry_replay_samples(cfg, index, options), options.seed.value_or(cfg.seed));
  const std::vector<double> nominal = ObstructionStudy::outputs(study.field(models::SeekerErrorState{}, true));
  GeometrySample r;
  study.compute(index, nominal, r);
  return geometry_replay_json(index, r, study.sampler().columns(), kOutputs);
}

std::string run_obstruction_study(const StudyConfig& study_cfg, const RunOptions& options) {
  StudyConfig cfg = study_cfg;
  const GeometryRunSize size = geometry_run_size(cfg, options, "--resume is not needed for a geometry study", [&] {
    return ObstructionStudy(study_cfg, 1, study_cfg.seed).sampler().dimension();
  });
  const ObstructionStudy study(cfg, size.samples, size.seed);
  const GeometryRun run = start_geometry_run(cfg, options, size);
  const FieldResult nominal_field = study.field(models::SeekerErrorState{}, true);
  const std::vector<double> nominal = ObstructionStudy::outputs(nominal_field);

  // Nominal clearance against pitch at yaw 0 and at the field's yaw limit (for the plot).
  const auto& g = *study.model().geometry;
  std::ostringstream sweep_dat;
  sweep_dat << "# pitch_deg  ring_housing_mm barrel_housing_mm barrel_ring_mm (yaw 0) | same at yaw max\n";
  for (double b : models::linspace(study.model().pitch_min, study.model().pitch_max, 31)) {
    sweep_dat << b / units::kRadPerDeg;
    for (double a : {0.0, study.model().yaw_max}) {
      const auto c = study.scenes().clearance(geometry::nominal_pose(a, b));
      sweep_dat << ' ' << 1e3 * c.ring_housing << ' ' << 1e3 * c.barrel_housing << ' ' << 1e3 * c.barrel_ring;
    }
    sweep_dat << '\n';
  }

  std::ostringstream sample_dat;
  sample_dat << "# min_fraction_pct min_fraction_shift_ppm min_clearance_mm clearance_shift_um\n";
  const GeometrySampleResults results = run_geometry_samples(
      cfg, run, study.sampler().columns(), kOutputs,
      [&](std::size_t i, GeometrySample& r) { study.compute(i, nominal, r); },
      [&](const GeometrySample& r) {
        sample_dat << r.outputs[0] << ' ' << r.outputs[3] << ' ' << r.outputs[4] << ' ' << r.outputs[8] << '\n';
      });

  json s;
  s["study"] = geometry_study_json(cfg, study.model().name, study.model().source);
  s["sampling"] = geometry_sampling_json(cfg, run, study.sampler().dimension());
  s["sampling"]["grid"] = {{"yaw_points", geometry_sections(cfg).geometry.yaw_points}, {"pitch_points", geometry_sections(cfg).geometry.pitch_points}};
  s["sampling"]["beam_rays"] = geometry_sections(cfg).geometry.beam_rays;
  s["sampling"]["clearance_per_sample"] = geometry_sections(cfg).geometry.clearance_per_sample;
  json nom;
  for (std::size_t k = 0; k < kNumOutputs; ++k) nom[kOutputs[k].name] = nominal[k];
  json map = json::array();
  for (std::size_t ia = 0; ia < study.yaw().size(); ++ia) {
    for (std::size_t ib = 0; ib < study.pitch().size(); ++ib) {
      const std::size_t k = ia * study.pitch().size() + ib;
      const auto& c = nominal_field.clearance[k];
      map.push_back({{"yaw_deg", study.yaw()[ia] / units::kRadPerDeg}, {"pitch_deg", study.pitch()[ib] / units::kRadPerDeg},
                     {"fraction", nominal_field.fraction[k]}, {"ring_housing_mm", 1e3 * c.ring_housing},
                     {"barrel_housing_mm", 1e3 * c.barrel_housing}, {"barrel_ring_mm", 1e3 * c.barrel_ring}});
    }
  }
  s["nominal"] = {{"outputs", nom}, {"grid", map},
                  {"geometry_mm", {{"yaw_span", 1e3 * g.yaw_span}, {"pitch_span", 1e3 * g.pitch_span},
                                   {"housing_radius", 1e3 * g.housing_radius}, {"window_radius", 1e3 * g.window_radius},
                                   {"aperture_radius", 1e3 * g.aperture_radius}, {"front_x", 1e3 * g.front_x}}},
                  {"clearance_below_warning", nominal[4] < 1e3 * geometry_sections(cfg).geometry.clearance_warn}};
  write_geometry_summary(s, cfg, run, kOutputs, results, study.sampler().columns());

  // Report.
  std::ostringstream t1;
  t1 << "<h2>Nominal design</h2>\n<p>Yaw span " << fmt_g(1e3 * g.yaw_span) << " mm, pitch span " << fmt_g(1e3 * g.pitch_span)
     << " mm; housing radius " << fmt_g(1e3 * g.housing_radius) << " mm, window opening radius " << fmt_g(1e3 * g.window_radius)
     << " mm, clear aperture radius " << fmt_g(1e3 * g.aperture_radius) << " mm, " << geometry_sections(cfg).geometry.beam_rays
     << " beam rays.</p>\n<table><tr><th class='l'>output</th><th>nominal</th></tr>\n";
  for (std::size_t k = 0; k < kNumOutputs; ++k) {
    if (k == 3 || k == 8) continue;
    t1 << "<tr><td class='l'>" << kOutputs[k].name << "</td><td>" << fmt_g(nominal[k]) << "</td></tr>\n";
  }
  t1 << "</table>\n";
  if (nominal[4] < 1e3 * geometry_sections(cfg).geometry.clearance_warn) {
    t1 << "<p class='bad'>The nominal clearance " << fmt_g(nominal[4]) << " mm is below the warning level "
       << fmt_g(1e3 * geometry_sections(cfg).geometry.clearance_warn) << " mm.</p>\n";
  }
  std::ostringstream map_dat;
  map_dat << "# yaw_deg pitch_deg fraction_pct min_clearance_mm\n";
  for (std::size_t ia = 0; ia < study.yaw().size(); ++ia) {
    for (std::size_t ib = 0; ib < study.pitch().size(); ++ib) {
      const std::size_t k = ia * study.pitch().size() + ib;
      map_dat << study.yaw()[ia] / units::kRadPerDeg << ' ' << study.pitch()[ib] / units::kRadPerDeg << ' '
              << 100 * nominal_field.fraction[k] << ' ' << 1e3 * nominal_field.clearance[k].min() << '\n';
    }
    map_dat << '\n';
  }
  std::vector<GeometryPlot> plots;
  plots.push_back({"map_fraction", map_dat.str(),
                   "set title 'Unobstructed share of the beam, nominal design [%]'\nset xlabel 'yaw [deg]'\n"
                   "set ylabel 'pitch [deg]'\n" + std::string(kViridisPalette) + "set cblabel '%'\n"
                   "plot 'map_fraction.dat' u 1:2:3 with image notitle\n",
                   "Unobstructed share of the beam over the field of regard (nominal)"});
  plots.push_back({"map_clearance", map_dat.str(),
                   "set title 'Least clearance of the moving frames, nominal design [mm]'\nset xlabel 'yaw [deg]'\n"
                   "set ylabel 'pitch [deg]'\n" + std::string(kViridisPalette) + "set cblabel 'mm'\n"
                   "plot 'map_clearance.dat' u 1:2:4 with image notitle\n",
                   "Least clearance (ring-housing, barrel-housing, barrel-ring) over the field (nominal)"});
  plots.push_back({"clearance_vs_pitch", sweep_dat.str(),
                   "set title 'Clearance against pitch, nominal design'\nset xlabel 'pitch [deg]'\nset ylabel 'mm'\n"
                   "set grid\nset key outside right\n"
                   "plot 'clearance_vs_pitch.dat' u 1:2 w l lw 2 t 'ring-housing, yaw 0', '' u 1:3 w l lw 2 t "
                   "'barrel-housing, yaw 0', '' u 1:4 w l lw 2 t 'barrel-ring, yaw 0', '' u 1:5 w l dt 2 lw 2 t "
                   "'ring-housing, yaw max', '' u 1:6 w l dt 2 lw 2 t 'barrel-housing, yaw max', '' u 1:7 w l dt 2 lw 2 t "
                   "'barrel-ring, yaw max'\n",
                   "Clearances of the moving frames against pitch at yaw 0 and at the yaw limit"});
  plots.push_back({"hist_min_fraction", sample_dat.str(),
                   histogram_script("hist_min_fraction.dat", 2, "Least beam share minus nominal, per sample", "shift [ppm]"),
                   "Change of the least unobstructed share by the shafting tolerances"});
  plots.push_back({"hist_clearance", sample_dat.str(),
                   histogram_script("hist_clearance.dat", 4, "Least clearance minus nominal, per sample", "shift [um]"),
                   "Change of the least clearance by the shafting tolerances"});
  finish_geometry_report(cfg, options, run, s, {t1.str()}, std::move(plots), results, kOutputs);
  return run.dir;
}

}  // namespace poise::studies
