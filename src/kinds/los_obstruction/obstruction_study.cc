#include "kinds/los_obstruction/obstruction_study.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <span>
#include <sstream>
#include <utility>

#include "core/format.h"
#include "core/units.h"
#include "engine/kind_interface/output_spec.h"
#include "engine/kind_interface/procedure_study.h"
#include "engine/report/report_plot.h"
#include "geometry/obstruction.h"
#include "geometry_studies/geometry_plots.h"
#include "geometry_studies/sampled_model_study.h"
#include "kinds/los_obstruction/obstruction_sections.h"
#include "model_files/seeker_geometry.h"
#include "model_files/seeker_model.h"
#include "sampling/design.h"

namespace poise::kinds::los_obstruction {
using namespace poise::engine;
using namespace poise::model_files;
using namespace poise::geometry_studies;
namespace {
using geometry::SeekerScenes;
using nlohmann::json;

constexpr OutputDeclaration kOutputs[] = {
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
  std::vector<double> fraction;                    // per grid point
  std::vector<SeekerScenes::Clearance> clearance;  // per grid point (empty if not computed)
};

// Sample i: the design point -> the seeker's error realization (SeekerSampler) -> the beam
// traced and the clearances measured at every grid point -> outputs, with the shifts from the
// nominal design's. No randomness of its own; no solver.
class ObstructionStudy final : public SampledModelStudy<ObstructionStudy> {
 public:
  ObstructionStudy(StudyConfig cfg, SeekerModel model, std::size_t n, std::uint64_t seed)
      : cfg_(std::move(cfg)),
        model_(std::move(model)),
        sampler_(model_),
        samples_(n),
        design_(make_design(cfg_, seed, n, sampler_.dimension())) {
    if (!model_.geometry) {
      throw ValidationError({InputError(SourceLocation{cfg_.file, 0, 0}, "study.model", "\"" + cfg_.model_path + "\"",
                                        "a seeker model with a [geometry] section (frames and housing)")});
    }
    const ObstructionSections& g = obstruction_sections(cfg_);
    scenes_ = std::make_unique<SeekerScenes>(*model_.geometry, seeker_scene_meshes(model_), g.beam_rays);
    yaw_ = models::linspace(model_.yaw_min, model_.yaw_max, g.yaw_points);
    pitch_ = models::linspace(model_.pitch_min, model_.pitch_max, g.pitch_points);
    for (std::size_t k = 0; k < sampler_.columns().size(); ++k) {
      declare_input({sampler_.columns()[k].name, sampler_.columns()[k].unit, "", sampler_.column_tolerances()[k]});
    }
    std::vector<OutputSpec> outputs;
    for (const auto& o : kOutputs) outputs.push_back({o.name, o.unit, o.description});
    declare_outputs(std::move(outputs));
    nominal_field_ = field(models::SeekerErrorState{}, true);
    nominal_ = ObstructionStudy::outputs(nominal_field_);
  }

  const StudyConfig& config() const override { return cfg_; }
  std::string model_name() const override { return model_.name; }
  std::string model_source() const override { return model_.source; }
  std::size_t samples() const { return samples_; }

  const sampling::Design& design() const { return design_; }
  /// What the sampler draws for these inputs (SI).
  auto realization_of(std::span<const double> si) const { return sampler_.state_of(si); }

  nlohmann::json details(const McResult&) const override;
  void report_sections(const McResult& mc, const std::string& plots_dir, bool plots, std::vector<std::string>& figures,
                       std::ostringstream& html) const override;
  /// The report's table of the nominal design (spans, radii, beam) and its outputs.
  void nominal_design_html(std::ostringstream& h) const;
  /// Gnuplot data of the nominal field maps (yaw, pitch, beam share, least clearance) and of
  /// the clearances against pitch at yaw 0 and at the yaw limit.
  std::string field_map_data() const;
  std::string clearance_sweep_data() const;

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
    for (const auto& c : f.clearance)
      rh = std::min(rh, c.ring_housing), bh = std::min(bh, c.barrel_housing), br = std::min(br, c.barrel_ring);
    const double cmin = std::min({rh, bh, br});
    return {100 * fmin, 100 * mean, 100.0 * static_cast<double>(full) / static_cast<double>(f.fraction.size()),
            0.0,        1e3 * cmin, 1e3 * rh,
            1e3 * bh,   1e3 * br,   0.0};
  }

  /// The outputs of one error realization, with the shifts from the nominal design's.
  std::vector<double> outputs_of(const models::SeekerErrorState& state) const {
    const std::vector<double>& nominal = nominal_;
    std::vector<double> o = outputs(field(state, obstruction_sections(cfg_).clearance_per_sample));
    o[3] = (o[0] - nominal[0]) * 1e4;  // pct -> ppm
    if (obstruction_sections(cfg_).clearance_per_sample) {
      o[8] = (o[4] - nominal[4]) * 1e3;  // mm -> um
    } else {
      for (std::size_t k = 4; k < kNumOutputs; ++k) o[k] = nominal[k];
      o[8] = 0.0;
    }
    return o;
  }

 private:
  StudyConfig cfg_;
  SeekerModel model_;
  SeekerSampler sampler_;
  std::size_t samples_;
  sampling::Design design_;
  std::unique_ptr<SeekerScenes> scenes_;
  FieldResult nominal_field_;
  std::vector<double> nominal_;
  std::vector<double> yaw_, pitch_;
};

json ObstructionStudy::details(const McResult&) const {
  const ObstructionSections& gs = obstruction_sections(cfg_);
  const auto& g = *model_.geometry;
  json nom;
  for (std::size_t k = 0; k < kNumOutputs; ++k) nom[kOutputs[k].name] = nominal_[k];
  json map = json::array();
  for (std::size_t ia = 0; ia < yaw_.size(); ++ia) {
    for (std::size_t ib = 0; ib < pitch_.size(); ++ib) {
      const std::size_t k = ia * pitch_.size() + ib;
      const auto& c = nominal_field_.clearance[k];
      map.push_back({{"yaw_deg", yaw_[ia] / units::kRadPerDeg},
                     {"pitch_deg", pitch_[ib] / units::kRadPerDeg},
                     {"fraction", nominal_field_.fraction[k]},
                     {"ring_housing_mm", 1e3 * c.ring_housing},
                     {"barrel_housing_mm", 1e3 * c.barrel_housing},
                     {"barrel_ring_mm", 1e3 * c.barrel_ring}});
    }
  }
  return {{"grid", {{"yaw_points", gs.yaw_points}, {"pitch_points", gs.pitch_points}}},
          {"beam_rays", gs.beam_rays},
          {"clearance_per_sample", gs.clearance_per_sample},
          {"nominal",
           {{"outputs", nom},
            {"grid", map},
            {"geometry_mm",
             {{"yaw_span", 1e3 * g.yaw_span},
              {"pitch_span", 1e3 * g.pitch_span},
              {"housing_radius", 1e3 * g.housing_radius},
              {"window_radius", 1e3 * g.window_radius},
              {"aperture_radius", 1e3 * g.aperture_radius},
              {"front_x", 1e3 * g.front_x}}},
            {"clearance_below_warning", nominal_[4] < 1e3 * gs.clearance_warn}}}};
}

void ObstructionStudy::nominal_design_html(std::ostringstream& h) const {
  const ObstructionSections& gs = obstruction_sections(cfg_);
  const auto& g = *model_.geometry;
  h << "<h2>Nominal design</h2>\n<p>Yaw span " << significant(1e3 * g.yaw_span, 6) << " mm, pitch span "
    << significant(1e3 * g.pitch_span, 6) << " mm; housing radius " << significant(1e3 * g.housing_radius, 6)
    << " mm, window opening radius " << significant(1e3 * g.window_radius, 6) << " mm, clear aperture radius "
    << significant(1e3 * g.aperture_radius, 6) << " mm, " << gs.beam_rays
    << " beam rays.</p>\n<table><tr><th class='l'>output</th><th>nominal</th></tr>\n";
  for (std::size_t k = 0; k < kNumOutputs; ++k) {
    if (k == 3 || k == 8) continue;  // the shifts: zero for the nominal design
    h << "<tr><td class='l'>" << kOutputs[k].name << "</td><td>" << significant(nominal_[k], 6) << " "
      << kOutputs[k].unit << "</td></tr>\n";
  }
  h << "</table>\n";
  if (nominal_[4] < 1e3 * gs.clearance_warn) {
    h << "<p class='bad'>The nominal clearance " << significant(nominal_[4], 6) << " mm is below the warning level "
      << significant(1e3 * gs.clearance_warn, 6) << " mm.</p>\n";
  }
}

std::string ObstructionStudy::field_map_data() const {
  std::ostringstream map_dat;
  map_dat << "# yaw_deg pitch_deg fraction_pct min_clearance_mm\n";
  for (std::size_t ia = 0; ia < yaw_.size(); ++ia) {
    for (std::size_t ib = 0; ib < pitch_.size(); ++ib) {
      const std::size_t k = ia * pitch_.size() + ib;
      map_dat << yaw_[ia] / units::kRadPerDeg << ' ' << pitch_[ib] / units::kRadPerDeg << ' '
              << 100 * nominal_field_.fraction[k] << ' ' << 1e3 * nominal_field_.clearance[k].min() << '\n';
    }
    map_dat << '\n';
  }
  return map_dat.str();
}

std::string ObstructionStudy::clearance_sweep_data() const {
  // Nominal clearance against pitch at yaw 0 and at the field's yaw limit.
  std::ostringstream sweep_dat;
  sweep_dat << "# pitch_deg  ring_housing_mm barrel_housing_mm barrel_ring_mm (yaw 0) | same at yaw max\n";
  for (double b : models::linspace(model_.pitch_min, model_.pitch_max, 31)) {
    sweep_dat << b / units::kRadPerDeg;
    for (double a : {0.0, model_.yaw_max}) {
      const auto c = scenes_->clearance(geometry::nominal_pose(a, b));
      sweep_dat << ' ' << 1e3 * c.ring_housing << ' ' << 1e3 * c.barrel_housing << ' ' << 1e3 * c.barrel_ring;
    }
    sweep_dat << '\n';
  }
  return sweep_dat.str();
}

// The report's own sections: the nominal design with its maps over the field, the clearance
// against pitch, and the shifts of the samples.
void ObstructionStudy::report_sections(const McResult& mc, const std::string& plots_dir, bool plots,
                                       std::vector<std::string>&, std::ostringstream& h) const {
  nominal_design_html(h);
  if (!plots) return;
  const std::string map_dat = field_map_data();
  const std::string sweep_dat = clearance_sweep_data();
  std::vector<GeometryPlot> figures;
  figures.push_back({"map_fraction", map_dat,
                     "set title 'Unobstructed share of the beam, nominal design [%]'\nset xlabel 'yaw [deg]'\n"
                     "set ylabel 'pitch [deg]'\n" +
                         std::string(kViridisPalette) +
                         "set cblabel '%'\n"
                         "plot 'map_fraction.dat' u 1:2:3 with image notitle, '' u 1:2:(sprintf(\"yaw %g deg, pitch "
                         "%g deg: %.4g %% unobstructed, least clearance %.3g mm\", $1, $2, $3, $4)) with labels "
                         "hypertext point pt 7 ps 0.3 lc rgb '#ffffff' notitle\n",
                     "Unobstructed share of the beam over the field of regard (nominal)"});
  figures.push_back({"map_clearance", map_dat,
                     "set title 'Least clearance of the moving frames, nominal design [mm]'\nset xlabel 'yaw [deg]'\n"
                     "set ylabel 'pitch [deg]'\n" +
                         std::string(kViridisPalette) +
                         "set cblabel 'mm'\n"
                         "plot 'map_clearance.dat' u 1:2:4 with image notitle, '' u 1:2:(sprintf(\"yaw %g deg, pitch "
                         "%g deg: least clearance %.3g mm, %.4g %% unobstructed\", $1, $2, $4, $3)) with labels "
                         "hypertext point pt 7 ps 0.3 lc rgb '#ffffff' notitle\n",
                     "Least clearance (ring-housing, barrel-housing, barrel-ring) over the field (nominal)"});
  figures.push_back(
      {"clearance_vs_pitch", sweep_dat,
       "set title 'Clearance against pitch, nominal design'\nset xlabel 'pitch [deg]'\nset ylabel 'mm'\n"
       "set key outside right\n"
       "plot 'clearance_vs_pitch.dat' u 1:2 w l lw 2 t 'ring-housing, yaw 0', '' u 1:3 w l lw 2 t "
       "'barrel-housing, yaw 0', '' u 1:4 w l lw 2 t 'barrel-ring, yaw 0', '' u 1:5 w l dt 2 lw 2 t "
       "'ring-housing, yaw max', '' u 1:6 w l dt 2 lw 2 t 'barrel-housing, yaw max', '' u 1:7 w l dt 2 lw 2 t "
       "'barrel-ring, yaw max'\n",
       "Clearances of the moving frames against pitch at yaw 0 and at the yaw limit"});
  if (!mc.ok_index.empty()) {
    std::ostringstream sample_dat;
    sample_dat << "# min_fraction_pct min_fraction_shift_ppm min_clearance_mm clearance_shift_um\n";
    for (std::size_t m = 0; m < mc.ok_index.size(); ++m) {
      sample_dat << mc.values[0][m] << ' ' << mc.values[3][m] << ' ' << mc.values[4][m] << ' ' << mc.values[8][m]
                 << '\n';
    }
    figures.push_back(
        {"hist_min_fraction", sample_dat.str(),
         histogram_script("hist_min_fraction.dat", 2, "Least beam share minus nominal, per sample", "shift [ppm]"),
         "Change of the least unobstructed share by the shafting tolerances"});
    figures.push_back(
        {"hist_clearance", sample_dat.str(),
         histogram_script("hist_clearance.dat", 4, "Least clearance minus nominal, per sample", "shift [um]"),
         "Change of the least clearance by the shafting tolerances"});
  }
  h << "<h2>Field of regard, nominal and as built</h2>\n" << geometry_figures_html(plots_dir, figures);
}

}  // namespace

std::unique_ptr<ProcedureStudy> make_obstruction_study(const StudyConfig& cfg,
                                                       const std::map<std::string, std::string>& model_overrides,
                                                       std::size_t samples, std::uint64_t seed) {
  return std::make_unique<ObstructionStudy>(cfg, load_seeker_model(cfg.model_path, model_overrides), samples, seed);
}

std::string validate_obstruction_study(const StudyConfig& cfg) {
  const ObstructionStudy study(cfg, load_seeker_model(cfg.model_path, cfg.overrides), cfg.samples, cfg.seed);
  const auto& g = *study.model().geometry;
  return fmt::format(
      "{}: valid. Study '{}' ({}) on model '{}': spans {:g} / {:g} mm, housing radius {:g} mm, window {:g} mm; "
      "{} random inputs, {} design, {} samples, seed {}; grid {} x {}, {} beam rays, clearance {}.",
      cfg.file, cfg.name, cfg.kind, study.model().name, 1e3 * g.yaw_span, 1e3 * g.pitch_span, 1e3 * g.housing_radius,
      1e3 * g.window_radius, study.sampler().dimension(), sampling::to_string(cfg.method), cfg.samples, cfg.seed,
      obstruction_sections(cfg).yaw_points, obstruction_sections(cfg).pitch_points, obstruction_sections(cfg).beam_rays,
      obstruction_sections(cfg).clearance_per_sample ? "per sample" : "nominal only");
}

}  // namespace poise::kinds::los_obstruction
