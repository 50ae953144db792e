#include "geometry_studies/geometry_runner_common.h"

#include "engine/references.h"
#include "engine/requirements.h"
#include "engine/sample_columns_h5.h"
#include "engine/report_figures.h"
#include "engine/study_kind.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>
#include <utility>

#include "core/error.h"
#include "core/version.h"
#include "sampling/statistics.h"
#include "engine/provenance.h"
#include "sampling/interrupt.h"
#include "engine/convergence.h"
#include "engine/checked_file.h"
#include "engine/result_io.h"
#include "engine/sample_driver.h"
#include "engine/sensitivity_output.h"

namespace poise::studies {
namespace fs = std::filesystem;
using nlohmann::json;

GeometryRunSize geometry_run_size(StudyConfig& cfg, const RunOptions& options, const std::string& resume_message,
                                  const std::function<std::size_t()>& dimension) {
  if (!options.resume.empty()) throw UsageError(resume_message);
  if (!options.until.empty()) throw UsageError("--until is for the seeker, gimbal, balancing-machine and platform kinds");
  GeometryRunSize size;
  size.samples = options.samples.value_or(cfg.samples);
  size.seed = options.seed.value_or(cfg.seed);
  if (size.samples == 0) throw UsageError("--samples must be at least 1");
  if (options.sensitivity_base > 0) {
    cfg.saltelli_base = options.sensitivity_base;
    cfg.saltelli_noise_group = false;  // a geometry sample is a pure function of its design point
    cfg.replicate_size = 0;
    size.samples = options.sensitivity_base * (dimension() + 2);
  }
  size.threads = options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return size;
}

GeometryRun start_geometry_run(const StudyConfig& cfg, const RunOptions& options, const GeometryRunSize& size) {
  GeometryRun run;
  run.size = size;
  run.dir = make_run_folder(options.results_root, cfg.name, options.out);
  run.started = now_iso8601();
  run.plots = options.plots && cfg.plots;
  if (options.progress) {
    std::fprintf(stderr, "poise: study %s -> %s\n  %zu samples (%s, seed %llu) on %d thread(s)\n", cfg.name.c_str(),
                 run.dir.c_str(), size.samples, sampling::to_string(cfg.method).c_str(),
                 static_cast<unsigned long long>(size.seed), size.threads);
  }
  run.t0 = std::chrono::steady_clock::now();
  return run;
}

GeometrySampleResults run_geometry_samples(const StudyConfig& cfg, const GeometryRun& run,
                                           const std::vector<InputColumn>& inputs,
                                           std::span<const GeometryOutputDef> outputs,
                                           const std::function<void(std::size_t, GeometrySample&)>& compute,
                                           const std::function<void(const GeometrySample&)>& on_ok) {
  CheckedFile csv((fs::path(run.dir) / "samples.csv").string(), false);
  std::string header = "sample,status";
  for (const auto& c : inputs) (header += ',') += c.name;
  for (const auto& o : outputs) (header += ',') += o.name;  // a const char*
  csv.write(header + ",message\n");
  GeometrySampleResults res;
  res.values.resize(outputs.size());
  sampling::InterruptGuard interrupts;
  StopRule rule({}, run.size.samples, cfg.max_failure_share, std::nullopt, 0, false);
  const DriveOutcome o = drive_samples<GeometrySample>(
      DriveSpec{0, run.size.samples, cfg.block, 1, run.size.threads, false}, [] { return 0; },
      [&](std::size_t i, int&, GeometrySample& r) { compute(i, r); },
      [&](std::size_t, std::span<const GeometrySample> block) {
        std::string rows;
        for (const auto& s : block) {
          rows += std::to_string(s.index) + ',' + (s.ok ? "ok" : "failed");
          for (double v : s.inputs) rows += ',' + csv_number(v);
          for (double v : s.outputs) rows += ',' + csv_number(v);
          rows += ',' + csv_text(s.message) + '\n';
          if (!s.ok) {
            ++res.failures;
            if (res.failed.size() < 100) res.failed.push_back({{"sample", s.index}, {"reason", s.message}});
            continue;
          }
          for (std::size_t k = 0; k < outputs.size(); ++k) res.values[k].push_back(s.outputs[k]);
          res.ok_index.push_back(s.index);
          on_ok(s);
        }
        csv.write(rows);  // the first refused write stops the run (WriteError)
      },
      [&](std::size_t completed) { return rule(res.values, res.ok_index, res.failures, completed); },
      [](const GeometrySample&, ByteWriter&) {}, [](ByteReader&, GeometrySample&) {});
  res.completed = o.completed;
  res.stop_reason = o.stop_reason;
  res.signal = o.signal;
  res.status = o.interrupted ? "interrupted" : rule.failed() ? "failed" : "complete";
  csv.close();
  res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - run.t0).count();
  return res;
}

json geometry_study_json(const StudyConfig& cfg, const std::string& model_name, const std::string& model_source) {
  return {{"name", cfg.name}, {"title", cfg.title}, {"kind", cfg.kind}, {"file", cfg.file},
          {"model_file", cfg.model_path}, {"model_name", model_name},
          {"model_source", model_source}, {"notes", cfg.notes}, {"overrides", cfg.overrides}};
}

json geometry_sampling_json(const StudyConfig& cfg, const GeometryRun& run, std::size_t dimension) {
  return {{"method", sampling::to_string(cfg.method)}, {"samples", run.size.samples}, {"seed", run.size.seed},
          {"threads", run.size.threads}, {"dimension", dimension}};
}

void write_geometry_summary(json& summary, const StudyConfig& cfg, const GeometryRun& run,
                            std::span<const GeometryOutputDef> outputs, const GeometrySampleResults& results,
                            const std::vector<InputColumn>& groups) {
  json out;
  std::vector<std::string> names;
  std::vector<sampling::Summary> summaries;
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    if (results.values[k].empty()) continue;
    summaries.push_back(sampling::summarize(results.values[k]));
    names.emplace_back(outputs[k].name);
    json j = summary_json(summaries.back());
    j["unit"] = outputs[k].unit;
    j["description"] = outputs[k].description;
    out[outputs[k].name] = j;
  }
  summary["status"] = results.status;
  if (results.signal != 0) summary["signal"] = results.signal;
  if (!results.stop_reason.empty()) summary["stop_reason"] = results.stop_reason;
  summary["sampling"]["samples"] = results.completed;
  summary["sampling"]["max_failure_share"] = cfg.max_failure_share;
  summary["outputs"] = out;
  summary["failures"] = {{"count", results.failures}, {"first", results.failed}};
  summary["sample_convergence"] = convergence_json(names, summaries, results.completed, 0, nullptr);
  {
    std::vector<OutputSpec> specs;
    for (const auto& o : outputs) specs.push_back({o.name, o.unit, o.description});
    summary["references"] = compare_references(declared_references(cfg, specs), specs, out, [&](const std::string& n) {
      for (std::size_t k = 0; k < outputs.size(); ++k) {
        if (n == outputs[k].name) return &results.values[k];
      }
      return static_cast<const std::vector<double>*>(nullptr);
    });
  }
  if (cfg.saltelli_base > 0 && results.status == "complete") {
    std::vector<std::string> output_names, group_names;
    std::vector<std::vector<double>> by_index(outputs.size(), std::vector<double>(results.completed, NAN));
    for (std::size_t k = 0; k < outputs.size(); ++k) {
      output_names.emplace_back(outputs[k].name);
      for (std::size_t m = 0; m < results.ok_index.size(); ++m) by_index[k][results.ok_index[m]] = results.values[k][m];
    }
    for (const auto& g : groups) group_names.push_back(g.name);
    summary["sensitivity"] = sensitivity_json(output_names, group_names, cfg.saltelli_base, by_index, run.size.seed);
  }
  {
    std::vector<OutputSpec> specs;
    for (const auto& o : outputs) specs.push_back({o.name, o.unit, o.description});
    add_answer(summary, cfg.requirements, specs, [&](const std::string& n) {
      OutputValues ov;
      for (std::size_t k = 0; k < outputs.size() && k < results.values.size(); ++k) {
        if (n == outputs[k].name) ov = {&results.values[k], &results.ok_index, 0, independent_samples(cfg)};
      }
      return ov;
    }, results.status, results.completed, cfg.saltelli_base > 0);
  }
  summary["provenance"] = {{"poise_version", kVersion}, {"git_commit", git_commit()},
                           {"study_file_sha1", file_sha1(cfg.file)}, {"model_file_sha1", file_sha1(cfg.model_path)},
                           {"seed", run.size.seed}, {"samples", run.size.samples}, {"threads", run.size.threads},
                           {"wall_time_s", results.wall_s}, {"started", run.started}, {"finished", now_iso8601()},
                           {"libraries", library_versions(run.plots)}};
  {
    std::vector<OutputSpec> specs;
    append_outputs(specs, "", outputs);
    summary["samples_h5"] = write_sample_columns_h5(
        (fs::path(run.dir) / "samples.csv").string(), (fs::path(run.dir) / "samples.h5").string(), {}, specs,
        {{"study", cfg.name}, {"kind", cfg.kind}, {"study_file", cfg.file}, {"method", sampling::to_string(cfg.method)},
         {"poise_version", kVersion}},
        {{"seed", run.size.seed}, {"planned_samples", run.size.samples}});
  }
  write_file_atomic((fs::path(run.dir) / "summary.json").string(), summary.dump(2) + "\n");
}

void finish_geometry_report(const StudyConfig& cfg, const RunOptions& options, const GeometryRun& run,
                            const json& summary, std::vector<std::string> tables, std::vector<GeometryPlot> plots,
                            const GeometrySampleResults& results, std::span<const GeometryOutputDef> outputs) {
  std::vector<std::string> figures;
  if (options.plots && cfg.plots) {
    const fs::path pdir = fs::path(run.dir) / "plots";
    fs::create_directories(pdir);
    std::vector<std::string> names;
    for (const auto& o : outputs) names.emplace_back(o.name);
    for (const auto& name : main_outputs(names, summary.value("references", json::array()), 2)) {
      for (std::size_t k = 0; k < outputs.size(); ++k) {
        if (name != outputs[k].name || k >= results.values.size()) continue;
        std::vector<FigureLine> lines;
        for (const auto& c : summary.value("references", json::array())) {
          if (c["output"] == name) lines.push_back({c["reference"].get<double>(), c["name"].get<std::string>()});
        }
        std::string why;
        distribution_figures(pdir, name, outputs[k].unit, results.values[k], results.ok_index, lines, figures, why);
        if (summary.contains("sensitivity")) sensitivity_tornado(pdir, summary["sensitivity"], name, figures, why);
      }
    }
  }
  if (summary.contains("sensitivity")) tables.insert(tables.begin(), sensitivity_html(summary["sensitivity"]));
  if (const std::string refs = references_html(summary.value("references", json::array())); !refs.empty()) {
    tables.insert(tables.begin(), refs);
  }
  if (summary["status"] != "complete") {
    tables.insert(tables.begin(), "<p><b>This run is " + summary["status"].get<std::string>() + "</b>: " +
                                      html_escape(summary.value("stop_reason", std::string("stopped by a signal"))) +
                                      ". The figures cover the samples that ran.</p>\n");
  }
  tables.push_back(convergence_html(summary["sample_convergence"]));
  write_geometry_report({run.dir, summary, std::move(tables), std::move(plots), options.plots && cfg.plots, figures});
  finish_run_status(summary["status"].get<std::string>(), summary.value("stop_reason", std::string()),
                    summary.value("signal", 0), summary["sampling"]["samples"].get<std::size_t>(), run.size.samples,
                    summary["failures"]["count"].get<std::size_t>(), run.dir, cfg.file);
}

std::size_t geometry_replay_samples(const StudyConfig& cfg, std::size_t index, const RunOptions& options) {
  const std::size_t n = options.samples.value_or(cfg.samples);
  if (index >= n) throw UsageError("sample index " + std::to_string(index) + " is outside 0.." + std::to_string(n - 1));
  return n;
}

json geometry_replay_json(std::size_t index, const GeometrySample& r, const std::vector<InputColumn>& inputs,
                          std::span<const GeometryOutputDef> outputs) {
  json j{{"sample", index}, {"status", r.ok ? "ok" : "failed"}};
  if (!r.ok) j["message"] = r.message;
  for (std::size_t k = 0; k < r.inputs.size(); ++k) j["inputs"][inputs[k].name] = r.inputs[k];
  for (std::size_t k = 0; k < outputs.size(); ++k) j["outputs"][outputs[k].name] = r.outputs[k];
  return j;
}

std::string fmt_g(double v, int prec) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

}  // namespace poise::studies
