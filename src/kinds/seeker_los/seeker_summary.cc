#include "kinds/seeker_los/seeker_summary.h"

#include <cmath>

#include "core/units.h"
#include "core/version.h"
#include "engine/provenance.h"
#include "engine/references.h"
#include "engine/result_io.h"
#include "kinds/seeker_los/seeker_los_sections.h"
#include "sampling/distributed.h"

namespace poise::studies {
using nlohmann::json;

json output_summary_json(const sampling::Summary& s, const std::string& unit, const std::string& desc) {
  json j = studies::summary_json(s);
  j["unit"] = unit;
  if (!desc.empty()) j["description"] = desc;
  return j;
}

// The seeker's outputs as declared.
std::vector<OutputSpec> seeker_output_specs() {
  std::vector<OutputSpec> specs;
  append_outputs(specs, "", kSeekerOutputs);
  return specs;
}

// The values of one seeker output of a run, for a requirement's verdict.
OutputValues seeker_values(const SeekerMcResult& mc, const std::string& name, std::size_t replicate_size,
                           bool independent) {
  OutputValues ov;
  for (std::size_t k = 0; k < mc.values.size() && k < kNumSeekerOutputs; ++k) {
    if (name == kSeekerOutputs[k].name) ov = {&mc.values[k], &mc.ok_index, replicate_size, independent};
  }
  return ov;
}

namespace {

// summary.json's "sampling" "inputs": each tolerance with its distribution and source.
json seeker_inputs_json(const SeekerModel& model) {
  json inputs = json::array();
  inputs.push_back({{"name", "load_deformation (k')"}, {"distribution", model.load_deformation.dist.describe(1.0, "")},
                    {"source", model.load_deformation.source}});
  auto tol_json = [&](const std::string& name, const ToleranceSpec& t) {
    inputs.push_back({{"name", name}, {"distribution", t.dist.describe(t.display_factor, t.display_unit)},
                      {"source", t.source}});
  };
  tol_json("yaw.perpendicularity (over " + units::format(model.yaw.span, "mm") + "; " + model.yaw.tilt_reading.describe() + ")",
           model.yaw.perpendicularity);
  tol_json("pitch.perpendicularity (over " + units::format(model.pitch.span, "mm") + ")", model.pitch.perpendicularity);
  tol_json("optics.axis_error (over " + units::format(model.barrel_length, "mm") + ")", model.optical_axis);
  for (const auto* a : {&model.yaw, &model.pitch}) {
    for (const auto& src : a->bearing_sources) {
      tol_json(std::string(a == &model.yaw ? "yaw." : "pitch.") + src.name + " (per bearing, order " +
                   csv_number(src.order) + (src.load_scaled ? ", x k')" : ")"),
               src.spec);
    }
  }
  return inputs;
}

}  // namespace

json seeker_summary(const SeekerRun& r, const SideResults& side, const RunOptions& options) {
  const StudyConfig& cfg = r.cfg;
  const SeekerModel& model = r.model;
  const SeekerMcResult& mc = r.mc;
  const SeekerLosSections& sec = seeker_sections(cfg);
  const std::size_t n = r.plan.samples, ran = r.ran, sensitivity_base = r.plan.sensitivity_base;
  const std::uint64_t seed = r.plan.seed;
  const std::string& status = r.status;
  std::vector<std::string> output_names;
  for (const auto& o : kSeekerOutputs) output_names.emplace_back(o.name);
  json s;
  s["contributions"] = side.contributions;
  s["study"] = {{"name", cfg.name}, {"title", cfg.title}, {"kind", cfg.kind}, {"file", cfg.file},
                {"model_file", cfg.model_path}, {"model_name", model.name}, {"model_source", model.source},
                {"notes", cfg.notes}, {"overrides", cfg.overrides}};
  const double req_arcsec = r.study.requirement_rad() * units::kArcsecPerRad;
  s["requirement"] = {{"as_written", sec.requirement_text}, {"arcsec", req_arcsec},
                      {"px", r.study.requirement_rad() / model.pixel_ifov},
                      {"pixel_ifov_arcsec", model.pixel_ifov * units::kArcsecPerRad},
                      {"pixel_ifov_source", model.pixel_ifov_source}};
  s["status"] = status;
  if (!mc.stop_reason.empty()) s["stop_reason"] = mc.stop_reason;
  s["sampling"] = {{"method", sampling::to_string(cfg.method)}, {"samples", ran}, {"planned_samples", n}, {"seed", seed},
                   {"threads", r.plan.threads}, {"mpi_ranks", sampling::Cluster::size()}, {"replicate_size", cfg.replicate_size},
                   {"max_failure_share", cfg.max_failure_share}, {"dimension", r.study.sampler().dimension()},
                   {"grid", {{"yaw_points", sec.yaw_points}, {"pitch_points", sec.pitch_points},
                             {"yaw_deg", {model.yaw_min / units::kRadPerDeg, model.yaw_max / units::kRadPerDeg}},
                             {"pitch_deg", {model.pitch_min / units::kRadPerDeg, model.pitch_max / units::kRadPerDeg}}}},
                   {"inputs", seeker_inputs_json(model)},
                   {"ci_note", cfg.replicate_size > 0
                                   ? "95% intervals of the per-sample outputs from the spread of the independent "
                                     "randomized replicates; pooled field figures assume independent samples"
                                   : "95% intervals assume independent samples; for lhs and sobol designs they are "
                                     "conservative for the mean, not necessarily for tail quantiles (measured on the "
                                     "LOS study: replicate p99.73 interval wider than this one); [sampling] "
                                     "replicate_size gives honest intervals"}};
  json outputs;
  for (std::size_t k = 0; k < mc.outputs.size(); ++k) {
    outputs[kSeekerOutputs[k].name] = output_summary_json(mc.outputs[k], kSeekerOutputs[k].unit, kSeekerOutputs[k].description);
  }
  s["outputs"] = outputs;
  if (mc.outputs.size() == kNumSeekerOutputs) {
    s["pooled_field_arcsec"] = output_summary_json(mc.pooled, "arcsec", "total LOS error over every (sample, grid point)");
    s["fraction_samples_meeting"] = estimate_json(mc.fraction_samples_ok);
    s["fraction_field_meeting"] = estimate_json(mc.fraction_field_ok);
  }
  {
    std::vector<OutputSpec> specs;
    for (const auto& o : kSeekerOutputs) specs.push_back({o.name, o.unit, o.description});
    std::map<std::string, const std::vector<double>*> by_name;
    for (std::size_t k = 0; k < mc.values.size() && k < kNumSeekerOutputs; ++k) by_name[kSeekerOutputs[k].name] = &mc.values[k];
    s["references"] = compare_references(declared_references(cfg, specs), specs, s["outputs"], [&](const std::string& output) {
      const auto it = by_name.find(output);
      return it == by_name.end() ? nullptr : it->second;
    });
  }
  s["failures"] = failures_json(mc.failures, ran, mc.failed, seed, cfg.file);
  if (!mc.field_file.is_null()) s["samples_h5"] = mc.field_file;
  s["sample_convergence"] = convergence_json(output_names, mc.outputs, ran, cfg.replicate_size, r.rule.until_json());
  if (sensitivity_base > 0 && status == "complete") {
    std::vector<std::string> groups;
    for (const auto& c : r.study.sampler().columns()) groups.push_back(c.name);
    std::vector<std::vector<double>> by_index(output_names.size(), std::vector<double>(ran, NAN));
    for (std::size_t k = 0; k < mc.values.size(); ++k) {
      for (std::size_t m = 0; m < mc.ok_index.size(); ++m) by_index[k][mc.ok_index[m]] = mc.values[k][m];
    }
    s["sensitivity"] = sensitivity_json(output_names, groups, sensitivity_base, by_index, seed, r.tolerances);
  }
  s["sweeps"] = side.sweeps;
  add_answer(s, r.requirements, seeker_output_specs(),
             [&](const std::string& name) { return seeker_values(mc, name, cfg.replicate_size, independent_samples(cfg)); }, status, ran,
             sensitivity_base > 0);
  s["provenance"] = {{"poise_version", kVersion}, {"git_commit", git_commit()},
                     {"study_file_sha1", file_sha1(cfg.file)}, {"model_file_sha1", file_sha1(cfg.model_path)},
                     {"seed", seed}, {"samples", ran}, {"threads", r.plan.threads}, {"mpi_ranks", sampling::Cluster::size()},
                     {"wall_time_s", mc.wall_seconds}, {"started", r.plan.started}, {"finished", now_iso8601()},
                     {"command_line_overrides", {{"samples", options.samples.has_value()}, {"seed", options.seed.has_value()}}},
                     {"libraries", library_versions(options.plots && cfg.plots)}};
  return s;
}

}  // namespace poise::studies
