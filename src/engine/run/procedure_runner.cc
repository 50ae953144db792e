#include "engine/run/procedure_runner.h"

#include "core/diagnostics.h"
#include "engine/run/stack_up.h"

#include "engine/kind_interface/study_kind.h"
#include "engine/report/report_figures.h"
#include "engine/report/run_report.h"
#include "engine/results/references.h"
#include "engine/results/requirements.h"
#include "engine/results/sample_columns_h5.h"
#include "engine/run/procedure_contributions.h"
#include "engine/run/procedure_resume.h"
#include "engine/run/procedure_sweeps.h"
#include "engine/run/sample_rows.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <thread>

#include "core/units.h"
#include "core/version.h"
#include "engine/report/report_plot.h"
#include "engine/results/provenance.h"
#include "engine/results/result_io.h"
#include "engine/results/sensitivity_output.h"
#include "engine/run/convergence.h"
#include "engine/run/run_plan.h"
#include "sampling/distributed.h"
#include "sampling/interrupt.h"

namespace poise::engine {
namespace fs = std::filesystem;
using nlohmann::json;

json replay_procedure_sample(const ProcedureStudy& study, std::size_t index) {
  const SampleResult r = study.replay(index);
  json j{{"sample", index}, {"status", r.ok ? "ok" : "failed"}};
  if (!r.ok) j["message"] = r.message;
  for (std::size_t k = 0; k < r.inputs.size(); ++k) j["inputs"][study.input_names()[k]] = r.inputs[k];
  for (std::size_t k = 0; k < r.outputs.size(); ++k) j["outputs"][study.output_names()[k]] = r.outputs[k];
  return j;
}

namespace {

// samples.csv's header: sample, status, the inputs, the outputs, solver_steps (a study with
// a solver) and message.
std::string csv_header(const ProcedureStudy& study) {
  std::string header = "sample,status";
  for (const auto& c : study.input_names()) header += "," + c;
  for (const auto& c : study.output_names()) header += "," + c;
  return header + (study.has_solver() ? ",solver_steps,message" : ",message");
}

// summary.json's statistics: outputs with their declared units, references, failures,
// convergence and (poise sensitivity) Sobol indices.
void add_statistics(json& s, const FinishedRun& f, const StopRule& rule) {
  const auto& names = f.study.output_names();
  const auto& specs = f.study.outputs();
  s["outputs"] = outputs_json(f.mc, specs, true);
  s["references"] =
      compare_references(declared_references(f.cfg, specs), specs, s["outputs"],
                         [&](const std::string& name) { return requirement_values(f.mc, specs, f.cfg)(name).values; });
  s["failures"] = failures_json(f.mc.failures, f.ran, f.mc.failed, f.plan.seed, f.cfg.file);
  s["failures"]["by_reason"] = f.mc.failure_reasons;
  s["sample_convergence"] = convergence_json(names, f.mc.outputs, f.ran, f.cfg.replicate_size, rule.until_json());
  if (f.plan.sensitivity_base > 0 && f.status == "complete") {
    std::vector<std::string> groups = f.study.design_dimension_names();
    if (f.cfg.saltelli_noise_group) {
      for (const auto& src : f.sources) groups.push_back("(within-sample randomness: " + src + ")");
    }
    // Every sample's value of output k (NaN where it failed), by sample index.
    std::vector<std::vector<double>> by_index(names.size(), std::vector<double>(f.ran, NAN));
    for (std::size_t k = 0; k < f.mc.values.size(); ++k) {
      for (std::size_t m = 0; m < f.mc.ok_index.size(); ++m) by_index[k][f.mc.ok_index[m]] = f.mc.values[k][m];
    }
    s["sensitivity"] = sensitivity_json(names, groups, f.plan.sensitivity_base, by_index, f.plan.seed, f.tolerances);
  }
}

// Each input's declared unit, by name.
json input_units_json(const std::vector<InputSpec>& inputs) {
  json units = json::object();
  for (const auto& i : inputs) units[i.name] = i.unit;
  return units;
}

json summary_of(const FinishedRun& f, const StopRule& rule, const RunOptions& options) {
  const StudyConfig& cfg = f.cfg;
  json s;
  s["status"] = f.status;
  if (!f.mc.stop_reason.empty()) s["stop_reason"] = f.mc.stop_reason;
  s["study"] = {{"name", cfg.name},
                {"title", cfg.title},
                {"kind", cfg.kind},
                {"file", cfg.file},
                {"model_file", cfg.model_path},
                {"model_name", f.study.model_name()},
                {"model_source", f.study.model_source()},
                {"notes", cfg.notes},
                {"overrides", cfg.overrides}};
  s["sampling"] = {{"method", sampling::to_string(cfg.method)},
                   {"samples", f.ran},
                   {"planned_samples", f.plan.samples},
                   {"seed", f.plan.seed},
                   {"threads", f.plan.threads},
                   {"mpi_ranks", sampling::Cluster::size()},
                   {"replicate_size", cfg.replicate_size},
                   {"max_failure_share", cfg.max_failure_share},
                   {"inputs", f.study.input_names()},
                   {"input_units", input_units_json(f.study.inputs())},
                   {"ci_note", cfg.replicate_size > 0
                                   ? "95% intervals from the spread of the independent randomized replicates"
                                   : "95% intervals assume independent samples; for lhs and sobol designs they are "
                                     "conservative for the mean, not necessarily for tail quantiles (measured on the "
                                     "LOS study: replicate p99.73 interval wider than this one); [sampling] "
                                     "replicate_size gives honest intervals"}};
  add_statistics(s, f, rule);
  add_answer(s, f.requirements, f.study.outputs(), requirement_values(f.mc, f.study.outputs(), cfg), f.status, f.ran,
             f.plan.sensitivity_base > 0);
  if (const json solver = f.study.solver_json(f.mc); !solver.is_null()) {
    s["solver"] = solver;
    if (f.rhs_uncounted > 0) {
      s["solver"]["rhs_evals_note"] = "rhs_evals leaves out " + std::to_string(f.rhs_uncounted) +
                                      " samples of the first part of the run (it was stopped before it could record "
                                      "its counters in run.json)";
    }
  }
  if (const json d = f.study.details(f.mc); !d.is_null()) s["details"] = d;
  if (f.plan.sensitivity_base == 0) {
    if (const json su = stack_up_json(f.study, f.mc, f.requirements); !su.is_null()) s["stack_up"] = su;
  }
  s["provenance"] = {{"poise_version", kVersion},
                     {"git_commit", git_commit()},
                     {"study_file_sha1", file_sha1(cfg.file)},
                     {"model_file_sha1", file_sha1(cfg.model_path)},
                     {"seed", f.plan.seed},
                     {"samples", f.ran},
                     {"threads", f.plan.threads},
                     {"mpi_ranks", sampling::Cluster::size()},
                     {"wall_time_s", f.mc.wall_seconds},
                     {"started", f.plan.started},
                     {"finished", now_iso8601()},
                     {"libraries", library_versions(options.plots && cfg.plots)},
                     {"resumed_after_sample", options.resume.empty() ? json(nullptr) : json(f.resumed)}};
  return s;
}

// What a probe study (one sample) tells the plan: the design's dimensions, their tolerance
// groups (one closed Sobol group per model tolerance drawn in several columns) and the
// within-sample randomness sources, the outputs.
struct DesignProbe {
  std::size_t dimensions = 0;
  bool own_randomness = false;
  ToleranceGroups tolerances;
  std::vector<std::string> sources, output_names;
};

DesignProbe probe_design(StudyConfig& cfg, const StudyFactory& make_study) {
  const std::unique_ptr<ProcedureStudy> probe = make_study(cfg, 1, cfg.seed);
  const std::vector<std::string> dimension_names = probe->design_dimension_names();
  std::vector<std::string> keys = probe->design_dimension_tolerances();
  keys.resize(dimension_names.size());
  DesignProbe d{dimension_names.size(), probe->has_own_randomness(), tolerance_groups(dimension_names, keys),
                probe->randomness_sources(), probe->output_names()};
  if (d.sources.empty()) d.sources = {"per-test draws, noise"};
  cfg.saltelli_groups = d.tolerances.closed_groups();
  cfg.saltelli_noise_sources = d.sources.size();
  return d;
}

// The run's stop rule and its folder's samples.h5, for a study that writes one of its own.
RunControl run_control(const std::shared_ptr<StopRule>& rule, RunFolder folder) {
  RunControl control;
  control.distributed = true;
  control.stop = [rule](const McResult& r) {
    return (*rule)(r.values, r.ok_index, r.failures, r.ok_index.size() + r.failures);
  };
  control.folder = std::move(folder);
  return control;
}

// A complete run's sweeps and contributions (each a set of further in-memory runs, spread
// over the MPI ranks: every rank calls this; `s` is filled on rank 0).
void add_sweeps_and_contributions(json& s, const StudyConfig& cfg, const ProcedureStudy& study, const RunPlan& plan,
                                  const std::vector<Requirement>& requirements, const StudyFactory& make_study,
                                  const RunOptions& options) {
  const bool talk = options.progress && sampling::Cluster::root();
  const std::size_t n = plan.samples;
  if (!cfg.sweeps.empty()) {
    s["sweeps"] =
        run_procedure_sweeps(cfg, make_study, n, plan.seed, plan.threads, talk, requirements, study.outputs());
  }
  if (cfg.contribution_samples > 0) {
    s["contributions"] =
        run_procedure_contributions(cfg, make_study, study.tolerance_keys(), std::min(cfg.contribution_samples, n),
                                    plan.seed, plan.threads, talk, study.outputs());
  }
}

// The samples a resumed run has in its samples.csv (none for a new run).
std::vector<SampleResult> resumed_samples(const StudyConfig& cfg, const ProcedureStudy& study, const RunPlan& plan,
                                          const RunOptions& options, const std::string& csv_path,
                                          const std::string& header) {
  if (options.resume.empty()) return {};
  if (!cfg.samples_csv) {
    throw UsageError("--resume: " + plan.dir + " was run with [output] samples_csv = false (" + cfg.file +
                     "): without samples.csv there is nothing to resume from; run it again, or keep samples.csv");
  }
  std::vector<SampleResult> done =
      read_done_samples(csv_path, header, study.input_names().size(), study.output_names().size(), study.has_solver());
  if (options.progress && sampling::Cluster::root()) {
    diagnostics::progress("  resuming: " + std::to_string(done.size()) + " of " + std::to_string(plan.samples) +
                          " samples already done");
  }
  return done;
}

}  // namespace

std::string run_procedure_study(const StudyConfig& cfg_in, const StudyFactory& make_study, const RunOptions& options,
                                const std::vector<Requirement>& requirements) {
  StudyConfig cfg = cfg_in;
  const bool root = sampling::Cluster::root();
  const DesignProbe probe = probe_design(cfg, make_study);
  const ToleranceGroups& tolerances = probe.tolerances;
  const std::vector<std::string>& sources = probe.sources;
  RunPlan plan = plan_run(
      cfg, options, [&] { return std::make_pair(probe.dimensions, probe.own_randomness); },
      [&] { return probe.output_names; });
  const std::size_t n = plan.samples;
  const std::unique_ptr<ProcedureStudy> owned = make_study(cfg, n, plan.seed);
  const ProcedureStudy& study = *owned;
  const std::optional<UntilTarget> until = plan_until(plan, study.output_names());
  announce_run(cfg, plan, until, options.progress);
  const std::string header = csv_header(study);
  const std::string csv_path = (fs::path(plan.dir) / "samples.csv").string();
  const std::vector<SampleResult> done = resumed_samples(cfg, study, plan, options, csv_path, header);
  CheckedFile csv = cfg.samples_csv ? open_samples_csv(plan, header, !options.resume.empty()) : CheckedFile{};
  sampling::InterruptGuard interrupts;
  auto rule = std::make_shared<StopRule>(study.output_names(), n, cfg.max_failure_share, until, cfg.replicate_size,
                                         options.progress && root);
  const std::string h5_path = (fs::path(plan.dir) / "samples.h5").string();
  const std::map<std::string, std::string> h5_text{{"study", cfg.name},
                                                   {"kind", cfg.kind},
                                                   {"study_file", cfg.file},
                                                   {"method", sampling::to_string(cfg.method)},
                                                   {"poise_version", kVersion}};
  const std::map<std::string, std::uint64_t> h5_numbers{{"seed", plan.seed}, {"planned_samples", n}};
  RunControl control = run_control(rule, RunFolder{h5_path, h5_text, h5_numbers});
  // A complete run that is not a sensitivity analysis has sweeps and contributions, which every
  // rank shares. Rank 0 knows how the samples ended and says so as soon as they have: the other
  // ranks start their share while it finishes the run's statistics and writes the folder.
  bool extra_runs = false;
  control.samples_done = [&](bool interrupted) {
    extra_runs = sampling::Cluster::any(root && !interrupted && !rule->failed() && plan.sensitivity_base == 0);
  };
  // Rows on disk are not written again.
  SampleRowWriter rows(csv, done.size(), study.has_solver());
  McResult mc = study.run(plan.threads, options.progress, cfg.samples_csv ? rows.sink() : SampleSink{}, done, control);
  if (!root) {  // rank 0 writes the folder
    json none;
    if (extra_runs) add_sweeps_and_contributions(none, cfg, study, plan, requirements, make_study, options);
    return "";
  }
  csv.close();
  const std::size_t ran = mc.completed;
  const std::size_t rhs_uncounted = add_resumed_counters(plan.manifest, done.size(), mc);
  const std::string status = mc.interrupted ? "interrupted" : rule->failed() ? "failed" : "complete";
  POISE_INVARIANT(extra_runs == (status == "complete" && plan.sensitivity_base == 0),
                  "the sweeps' go-ahead shared with the other ranks is the run's status");
  // The counters samples.csv does not hold, for a later --resume (steps are in its rows).
  plan.manifest["solver_counters"] = {{"samples", ran}, {"rhs_evals", mc.rhs_evals}};
  finish_manifest(plan, status, ran);

  const FinishedRun f{cfg, study, plan, mc, ran, done.size(), rhs_uncounted, status, sources, tolerances, requirements};
  json s = summary_of(f, *rule, options);
  // samples.h5: a study's own (written during the run); else the inputs and outputs as named
  // columns, from the finished samples.csv.
  s["samples_h5"] = mc.samples_h5     ? *mc.samples_h5
                    : cfg.samples_csv ? write_sample_columns_h5(csv_path, h5_path, study.inputs(), study.outputs(),
                                                                h5_text, h5_numbers)
                                      : json(nullptr);
  if (extra_runs) add_sweeps_and_contributions(s, cfg, study, plan, requirements, make_study, options);
  write_file_atomic((fs::path(plan.dir) / "summary.json").string(), s.dump(2) + "\n");
  const fs::path pdir = fs::path(plan.dir) / "plots";
  fs::create_directories(pdir);
  write_file_atomic((fs::path(plan.dir) / "report.html").string(),
                    run_report_html(s, f, pdir, options.plots && cfg.plots));
  finish_run_status(status, mc.stop_reason, mc.signal, ran, n, mc.failures, plan.dir, cfg.file);
  return plan.dir;
}

}  // namespace poise::engine
