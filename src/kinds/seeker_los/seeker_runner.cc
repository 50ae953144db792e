#include "kinds/seeker_los/seeker_runner.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <thread>

#include "core/units.h"
#include "core/version.h"
#include "sampling/distributed.h"
#include "sampling/interrupt.h"
#include "engine/convergence.h"
#include "engine/provenance.h"
#include "engine/references.h"
#include "engine/requirements.h"
#include "engine/study_kind.h"
#include "engine/result_io.h"
#include "engine/run_plan.h"
#include "engine/sensitivity_output.h"
#include "engine/toml_reader.h"
#include "kinds/seeker_los/seeker_los_sections.h"
#include "kinds/seeker_los/seeker_los_study.h"
#include "kinds/seeker_los/seeker_report.h"
#include "kinds/seeker_los/seeker_summary.h"

namespace poise::studies {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// The study's model with its overrides and `extra` on top.
SeekerModel load_model(const StudyConfig& cfg, const std::map<std::string, std::string>& extra = {}) {
  auto overrides = cfg.overrides;
  for (const auto& [k, v] : extra) overrides[k] = v;
  return load_seeker_model(cfg.model_path, overrides);
}

// samples.csv rows of each block: the rows' text is made on all threads (64 numbers a row),
// 64 rows to a piece, and the pieces written in order; their strings keep their capacity from
// block to block. Rows a resumed run already has on disk are skipped.
class SeekerRowWriter {
 public:
  SeekerRowWriter(CheckedFile& csv, int threads, std::size_t rows_on_disk)
      : csv_(csv), arena_(std::max(1, threads)), rows_on_disk_(rows_on_disk) {}

  void operator()(std::span<const SeekerSampleResult> block) {
    const std::size_t n_pieces = (block.size() + kRowsPerPiece - 1) / kRowsPerPiece;
    if (pieces_.size() < n_pieces) pieces_.resize(n_pieces);
    arena_.execute([&] {
      tbb::parallel_for(std::size_t{0}, n_pieces, [&](std::size_t piece) { format_piece(block, piece); });
    });
    for (std::size_t piece = 0; piece < n_pieces; ++piece) {
      if (!pieces_[piece].empty()) csv_.write(pieces_[piece]);  // the first refused write stops the run (WriteError)
    }
  }

 private:
  static constexpr std::size_t kRowsPerPiece = 64;

  void format_piece(std::span<const SeekerSampleResult> block, std::size_t piece) {
    std::string& text = pieces_[piece];
    text.clear();
    std::vector<char> row;
    const std::size_t end = std::min(block.size(), (piece + 1) * kRowsPerPiece);
    for (std::size_t k = piece * kRowsPerPiece; k < end; ++k) {
      const SeekerSampleResult& s = block[k];
      if (s.index < rows_on_disk_) continue;
      // The numbers into one buffer, then one append (not one per number).
      row.resize(32 + kCsvNumberChars * (s.inputs.size() + s.outputs.size()));
      char* at = std::to_chars(row.data(), row.data() + 24, s.index).ptr;
      const std::string_view status = s.ok ? ",ok" : ",failed";
      at = std::copy(status.begin(), status.end(), at);
      for (double v : s.inputs) at = put_csv_number(at, v);
      for (double v : s.outputs) at = put_csv_number(at, v);
      *at++ = ',';
      text.append(row.data(), at);
      if (!s.message.empty()) text += csv_text(s.message);
      text += '\n';
    }
  }

  CheckedFile& csv_;
  tbb::task_arena arena_;
  std::size_t rows_on_disk_;
  std::vector<std::string> pieces_;
};

// Sweeps and contributions of a complete run (`extras`), from `ran` samples run.
SideResults run_side_studies(const StudyConfig& cfg, const SeekerModel& model, std::uint64_t seed, int threads,
                             std::size_t run_samples, std::size_t ran, std::size_t contribution_samples, std::size_t keep_grid_bytes,
                             bool extras, bool progress, const std::vector<Requirement>& requirements) {
  // Sweeps and contributions keep no file of their grid values; the memory setting holds.
  SeekerRunControl side_runs;
  side_runs.keep_grid_bytes = keep_grid_bytes;
  // They are many short runs (a sweep value, a tolerance set to zero), each a whole run with
  // its own serial moments: run side by side, one thread each, on the run's threads. A run's
  // figures do not depend on its thread count, so this changes no result, only the order.
  struct SideRun {
    std::map<std::string, std::string> overrides;
    std::size_t samples = 0;
    SeekerMcResult result;
  };
  std::vector<SideRun> side;
  for (const auto& sw : extras ? cfg.sweeps : std::vector<SweepSpec>{}) {
    for (const auto& v : sw.values) side.push_back({{{sw.parameter, v}}, sweep_samples(sw, run_samples), {}});
  }
  const std::size_t first_contribution = side.size();
  const bool contribute = extras && contribution_samples > 0;
  const std::size_t nc = std::min(contribution_samples, ran);
  if (contribute) {
    side.push_back({{}, nc, {}});  // all tolerances
    for (const auto& key : model.tolerance_keys()) side.push_back({{{key + ".tolerance", "0 mm"}}, nc, {}});
  }
  if (progress && !side.empty()) {
    std::fprintf(stderr, "  sweeps and contributions: %zu runs side by side\n", side.size());
  }
  tbb::task_arena side_arena(std::max(1, threads));
  side_arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, side.size(), [&](std::size_t k) {
      SideRun& job = side[k];
      const SeekerModel model_v = job.overrides.empty() ? model : load_model(cfg, job.overrides);
      job.result = SeekerLosStudy(cfg, model_v, job.samples, seed).run(1, false, {}, side_runs);
    }, tbb::simple_partitioner());
  });

  // Sweeps: the same seed at every value (common random numbers), so differences between
  // values are the design's, not the sampling noise's.
  json sweeps = json::array();
  std::size_t job = 0;
  for (const auto& sw : extras ? cfg.sweeps : std::vector<SweepSpec>{}) {
    json js{{"parameter", sw.parameter}, {"samples", sweep_samples(sw, run_samples)}, {"points", json::array()}};
    for (const auto& v : sw.values) {
      const SeekerMcResult& r = side[job++].result;
      json p{{"value", v}, {"value_si", units::parse_quantity(v).value}, {"failures", r.failures}};
      if (!r.outputs.empty()) {
        p["los_max_arcsec"] = output_summary_json(r.outputs[0], "arcsec", "");
        p["fraction_samples_meeting"] = estimate_json(r.fraction_samples_ok);
        p["pooled_arcsec"] = output_summary_json(r.pooled, "arcsec", "");
        // The same shape as every kind's sweep points: each output, each requirement's verdict.
        json outs = json::object();
        for (std::size_t k = 0; k < r.outputs.size() && k < kNumSeekerOutputs; ++k) {
          outs[kSeekerOutputs[k].name] = output_summary_json(r.outputs[k], kSeekerOutputs[k].unit, "");
        }
        p["outputs"] = outs;
        p["requirements"] = judge_requirements(requirements, seeker_output_specs(), [&](const std::string& name) {
          return seeker_values(r, name, cfg.replicate_size, independent_samples(cfg));
        });
      }
      js["points"].push_back(p);
    }
    sweeps.push_back(js);
  }

  // Contributions: each tolerance set to zero in turn, same seed (common random numbers);
  // the drop of the statistics is that tolerance's share of the error.
  json contributions = json::array();
  if (contribute) {
    auto stats = [&](const SeekerMcResult& r) {
      return json{{"los_max_p50", r.outputs[0].p50.value}, {"los_max_p95", r.outputs[0].p95.value},
                  {"los_max_p99_73", r.outputs[0].p99_73.value}, {"pooled_p95", r.pooled.p95.value},
                  {"fraction_samples_meeting", r.fraction_samples_ok.value}};
    };
    const SeekerMcResult& all = side[first_contribution].result;
    if (!all.outputs.empty()) {
      contributions.push_back({{"without", "(nothing: all tolerances)"}, {"samples", nc}, {"stats", stats(all)}});
      std::size_t k = first_contribution + 1;
      for (const auto& key : model.tolerance_keys()) {
        const SeekerMcResult& r = side[k++].result;
        if (!r.outputs.empty()) contributions.push_back({{"without", key}, {"samples", nc}, {"stats", stats(r)}});
      }
    }
  }

  return {sweeps, contributions};
}

}  // namespace

std::string validate_seeker_study(const StudyConfig& cfg) {
  const SeekerModel model = load_model(cfg);
  const SeekerLosSections& sec = seeker_sections(cfg);
  SeekerSampler sampler(model);
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%s: valid. Study '%s' (%s) on model '%s': %zu random inputs, %s design, %zu "
                "samples, seed %llu, grid %zu x %zu over yaw [%g, %g] deg, pitch [%g, %g] deg, "
                "requirement %s, %zu sweep(s).",
                cfg.file.c_str(), cfg.name.c_str(), cfg.kind.c_str(), model.name.c_str(),
                sampler.dimension(), sampling::to_string(cfg.method).c_str(), cfg.samples,
                static_cast<unsigned long long>(cfg.seed), sec.yaw_points, sec.pitch_points,
                model.yaw_min / units::kRadPerDeg, model.yaw_max / units::kRadPerDeg,
                model.pitch_min / units::kRadPerDeg, model.pitch_max / units::kRadPerDeg,
                sec.requirement_text.c_str(), cfg.sweeps.size());
  return buf;
}

json replay_seeker_sample(const StudyConfig& cfg, std::size_t index, const RunOptions& options) {
  const SeekerModel model = load_model(cfg);
  const std::size_t n = options.samples.value_or(cfg.samples);
  if (index >= n) throw UsageError("sample index " + std::to_string(index) + " is outside 0.." + std::to_string(n - 1));
  SeekerLosStudy study(cfg, model, n, options.seed.value_or(cfg.seed));
  auto ws = study.make_workspace();
  SeekerSampleResult r;
  study.compute(index, ws, r);
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

std::string run_seeker_study(const StudyConfig& file_cfg, const RunOptions& options,
                             const std::vector<Requirement>& requirements) {
  StudyConfig cfg = file_cfg;
  const SeekerModel model = load_model(cfg);
  const SeekerLosSections& sec = seeker_sections(cfg);
  const bool root = sampling::Cluster::root();
  // Sensitivity: one closed Sobol group per model tolerance drawn in several columns.
  ToleranceGroups tolerances;
  {
    const SeekerSampler sampler(model);
    std::vector<std::string> names;
    for (const auto& c : sampler.columns()) names.push_back(c.name);
    tolerances = tolerance_groups(names, sampler.column_tolerances());
    cfg.saltelli_groups = tolerances.closed_groups();
  }
  RunPlan plan = plan_run(cfg, options, [&] {
    // A LOS sample is a pure function of its design point: no randomness of its own.
    return std::make_pair(SeekerSampler(model).dimension(), false);
  }, [] {
    std::vector<std::string> names;
    for (const auto& o : kSeekerOutputs) names.emplace_back(o.name);
    return names;
  });
  const std::size_t n = plan.samples;
  const std::uint64_t seed = plan.seed;
  const int threads = plan.threads;
  const std::string& dir = plan.dir;
  const std::size_t sensitivity_base = plan.sensitivity_base;
  std::size_t rows_on_disk = 0;  // a resumed run's complete samples.csv rows
  std::vector<std::string> output_names;
  for (const auto& o : kSeekerOutputs) output_names.emplace_back(o.name);
  const std::optional<UntilTarget> until = plan_until(plan, output_names);
  announce_run(cfg, plan, until, options.progress);
  SeekerLosStudy study(cfg, model, n, seed);

  // samples.csv, streamed in sample order. A resumed run recomputes its samples (a LOS
  // sample takes microseconds and the pooled field statistics need every grid value) and
  // appends the rows the file lacks.
  std::string header = "sample,status";
  for (const auto& c : study.sampler().columns()) header += "," + c.name;
  for (const auto& o : kSeekerOutputs) header += std::string(",") + o.name;
  header += ",message";
  const std::string csv_path = (fs::path(dir) / "samples.csv").string();
  if (!options.resume.empty() && root) {
    const std::string rows = read_complete_rows(csv_path, header);
    rows_on_disk = static_cast<std::size_t>(std::count(rows.begin(), rows.end(), '\n'));
  }
  CheckedFile csv = open_samples_csv(plan, header, !options.resume.empty());
  sampling::InterruptGuard interrupts;
  auto rule = std::make_shared<StopRule>(output_names, n, cfg.max_failure_share, until, cfg.replicate_size,
                                         options.progress && root);
  SeekerRunControl control;
  control.distributed = true;
  // The grid values of every sample go to samples.h5 (a resumed run recomputes and rewrites
  // it whole: the same data); samples.csv keeps the inputs and the scalar outputs.
  control.field_file = (fs::path(dir) / "samples.h5").string();
  control.keep_grid_bytes = sec.grid_values_in_memory_mb << 20;
  control.field_attributes = {{"study", cfg.name}, {"kind", cfg.kind}, {"study_file", cfg.file},
                              {"method", sampling::to_string(cfg.method)}, {"poise_version", kVersion}};
  control.field_number_attributes = {{"seed", seed}, {"planned_samples", n}};
  control.stop = [rule](const std::vector<std::vector<double>>& v, const std::vector<std::size_t>& ok, std::size_t f,
                        std::size_t c) { return (*rule)(v, ok, f, c); };
  SeekerRowWriter rows(csv, threads, rows_on_disk);
  const SeekerMcResult mc = study.run(threads, options.progress, [&](std::span<const SeekerSampleResult> block) { rows(block); },
                                      control);
  if (!root) return "";  // rank 0 writes the folder
  csv.close();
  const std::size_t ran = mc.completed;
  const std::string status = mc.interrupted ? "interrupted" : rule->failed() ? "failed" : "complete";
  finish_manifest(plan, status, ran);
  const bool extras = status == "complete" && sensitivity_base == 0;  // sweeps and contributions

  const SideResults side = run_side_studies(cfg, model, seed, threads, n, ran, sec.contribution_samples,
                                            control.keep_grid_bytes, extras, options.progress, requirements);
  const json s = seeker_summary({cfg, model, study, mc, plan, *rule, tolerances, requirements, status, ran}, side, options);
  write_file_atomic((fs::path(dir) / "summary.json").string(), s.dump(2) + "\n");
  ReportInputs rep{dir, s, mc, study.grid().alpha(), study.grid().beta(), options.plots && cfg.plots};
  write_report(rep);
  finish_run_status(status, mc.stop_reason, mc.signal, ran, n, mc.failures, dir, cfg.file);
  return dir;
}

}  // namespace poise::studies
