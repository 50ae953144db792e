#include "engine/procedure_runner.h"

#include "engine/references.h"
#include "engine/report_figures.h"
#include "engine/study_kind.h"

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
#include "sampling/interrupt.h"
#include "engine/convergence.h"
#include "engine/provenance.h"
#include "engine/run_plan.h"
#include "engine/sensitivity_output.h"
#include "engine/report_plot.h"
#include "engine/result_io.h"

namespace poise::studies {
namespace fs = std::filesystem;
using nlohmann::json;

void collect_samples(McResult& r, std::span<const SampleResult> block) {
  for (const auto& s : block) {
    r.solver_steps += s.solver_steps;
    r.rhs_evals += s.rhs_evals;
    if (!s.ok) {
      ++r.failures;
      if (r.failed.size() < 100) r.failed.emplace_back(s.index, s.message);
      ++r.failure_reasons[s.message.substr(0, s.message.find(": "))];
      continue;
    }
    if (r.values.size() < s.outputs.size()) r.values.resize(s.outputs.size());
    for (std::size_t k = 0; k < s.outputs.size(); ++k) r.values[k].push_back(s.outputs[k]);
    r.ok_index.push_back(s.index);
  }
}

void summarize_outputs(McResult& r) {
  r.outputs.clear();
  if (r.values.empty() || r.values[0].empty()) return;
  for (const auto& v : r.values) r.outputs.push_back(summarize_output(v, r.ok_index, r.replicate_size));
}

void encode_result(const SampleResult& r, ByteWriter& w) {
  encode_sample_fields(r, w);
  w.put(r.solver_steps);
  w.put(r.rhs_evals);
}

void decode_result(ByteReader& rd, SampleResult& r) {
  decode_sample_fields(rd, r);
  r.solver_steps = rd.get<long>();
  r.rhs_evals = rd.get<long>();
}

std::string unit_of_output(const std::string& name) {
  static const std::pair<const char*, const char*> kSuffixes[] = {
      {"_mNm", "mN*m"}, {"_deg", "deg"}, {"_gmm", "g*mm"}, {"_kgm", "kg*m"}, {"_kgm2", "kg*m^2"},
      {"_pct", "%"},    {"_mN", "mN"},   {"_N", "N"},      {"_g", "g"},     {"_mm", "mm"},
      {"_arcsec", "arcsec"},
      {"_Hz", "Hz"},    {"_per_mm", "1/mm"}, {"_ratio", "1"}, {"_um", "um"}, {"_min", "min"}, {"_s", "s"}, {"_MPa", "MPa"}, {"_urad", "urad"}};
  // The longest matching suffix wins ("_per_mm" before "_mm").
  std::size_t best = 0;
  const char* found = "";
  for (const auto& [suffix, unit] : kSuffixes) {
    const std::size_t n = std::char_traits<char>::length(suffix);
    if (n > best && name.size() > n && name.compare(name.size() - n, n, suffix) == 0) {
      best = n;
      found = unit;
    }
  }
  return found;
}

namespace {

std::string fmt(double v, int prec = 9) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

}  // namespace

json replay_procedure_sample(const ProcedureStudy& study, std::size_t index) {
  const SampleResult r = study.replay(index);
  json j{{"sample", index}, {"status", r.ok ? "ok" : "failed"}};
  if (!r.ok) j["message"] = r.message;
  for (std::size_t k = 0; k < r.inputs.size(); ++k) j["inputs"][study.input_names()[k]] = r.inputs[k];
  for (std::size_t k = 0; k < r.outputs.size(); ++k) j["outputs"][study.output_names()[k]] = r.outputs[k];
  return j;
}

namespace {

// Samples already in an interrupted run's samples.csv (their outputs, status, solver steps
// and failure reasons): complete lines only, in order from 0; a partial last line is cut off
// the file. Throws if the header is not this study's.
std::vector<SampleResult> read_done_samples(const std::string& csv_path, const std::string& header,
                                                  std::size_t n_inputs, std::size_t n_outputs) {
  std::vector<SampleResult> done;
  std::istringstream lines(read_complete_rows(csv_path, header));
  std::string line;
  while (std::getline(lines, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    if (cells.size() != 2 + n_inputs + n_outputs + 2) {
      throw Error("--resume: " + csv_path + " row " + std::to_string(done.size() + 2) + " has " +
                  std::to_string(cells.size()) + " cells, expected " + std::to_string(4 + n_inputs + n_outputs));
    }
    SampleResult r;
    r.index = std::stoul(cells[0]);
    if (r.index != done.size()) throw Error("--resume: samples.csv rows are not in order at sample " + cells[0]);
    r.ok = cells[1] == "ok";
    // Only what the statistics and the stop rule read: the inputs stay on disk, and an ok
    // row's message is empty (memory per resumed row: its outputs).
    r.outputs.reserve(n_outputs);
    for (std::size_t k = 0; k < n_outputs; ++k) r.outputs.push_back(std::stod(cells[2 + n_inputs + k]));
    r.solver_steps = std::stol(cells[2 + n_inputs + n_outputs]);
    if (!r.ok) r.message = cells.back();
    done.push_back(std::move(r));
  }
  return done;
}

// A resumed run's samples come back from samples.csv with their solver steps but not their
// right-hand-side evaluations: those the interrupted part recorded in run.json are added to
// `mc`. Returns how many of the `resumed` samples have none recorded (a run killed before it
// could write run.json), 0 when the count is whole.
std::size_t add_resumed_counters(const json& manifest, std::size_t resumed, McResult& mc) {
  if (resumed == 0) return 0;
  const auto it = manifest.find("solver_counters");
  if (it == manifest.end() || !it->is_object()) return resumed;
  const std::size_t counted = std::min(it->value("samples", std::size_t{0}), resumed);
  mc.rhs_evals += it->value("rhs_evals", 0L);
  return resumed - counted;
}

}  // namespace

std::string run_procedure_study(const StudyConfig& cfg_in, const StudyFactory& make_study, const RunOptions& options) {
  StudyConfig cfg = cfg_in;
  const bool root = sampling::Cluster::root();
  const int ranks = sampling::Cluster::size();
  // One probe study (one sample) answers what the plan needs: the design's dimensions, their
  // tolerance keys and randomness sources (Sobol groups), and the output names.
  const std::unique_ptr<ProcedureStudy> probe = make_study(cfg, 1, cfg.seed);
  const std::vector<std::string> dimension_names = probe->design_dimension_names();
  std::vector<std::string> keys = probe->design_dimension_tolerances();
  keys.resize(dimension_names.size());
  // Sensitivity: one closed Sobol group per model tolerance drawn in several columns.
  const ToleranceGroups tolerances = tolerance_groups(dimension_names, keys);
  cfg.saltelli_groups = tolerances.closed_groups();
  std::vector<std::string> sources = probe->randomness_sources();  // of the within-sample randomness
  if (sources.empty()) sources = {"per-test draws, noise"};
  cfg.saltelli_noise_sources = sources.size();
  RunPlan plan = plan_run(cfg, options, [&] {
    return std::make_pair(dimension_names.size(), probe->has_own_randomness());
  }, [&] { return probe->output_names(); });
  const std::size_t n = plan.samples;
  const std::uint64_t seed = plan.seed;
  const int threads = plan.threads;
  const std::string& dir = plan.dir;
  const std::string& started = plan.started;
  const std::size_t sensitivity_base = plan.sensitivity_base;
  const std::unique_ptr<ProcedureStudy> owned = make_study(cfg, n, seed);
  const ProcedureStudy& study = *owned;
  const std::optional<UntilTarget> until = plan_until(plan, study.output_names());
  announce_run(cfg, plan, until, options.progress);
  std::string header = "sample,status";
  for (const auto& c : study.input_names()) header += "," + c;
  for (const auto& c : study.output_names()) header += "," + c;
  header += ",solver_steps,message";
  const std::string csv_path = (fs::path(dir) / "samples.csv").string();
  std::vector<SampleResult> done;
  if (!options.resume.empty()) {
    done = read_done_samples(csv_path, header, study.input_names().size(), study.output_names().size());
    if (options.progress && root) std::fprintf(stderr, "  resuming: %zu of %zu samples already done\n", done.size(), n);
  }
  CheckedFile csv = open_samples_csv(plan, header, !options.resume.empty());
  sampling::InterruptGuard interrupts;
  auto rule = std::make_shared<StopRule>(study.output_names(), n, cfg.max_failure_share, until, cfg.replicate_size,
                                         options.progress && root);
  RunControl control;
  control.distributed = true;
  control.stop = [rule](const McResult& r) { return (*rule)(r.values, r.ok_index, r.failures, r.ok_index.size() + r.failures); };
  McResult mc = study.run(threads, options.progress, [&](std::span<const SampleResult> block) {
    std::string rows;
    for (const auto& s : block) {
      rows += std::to_string(s.index) + ',' + (s.ok ? "ok" : "failed");
      for (double v : s.inputs) rows += ',' + csv_number(v);
      for (double v : s.outputs) rows += ',' + csv_number(v);
      rows += ',' + std::to_string(s.solver_steps) + ',' + csv_text(s.message) + '\n';
    }
    csv.write(rows);  // the first refused write stops the run (WriteError)
  }, done, control);
  if (!root) return "";  // rank 0 writes the folder
  csv.close();
  const std::size_t ran = mc.completed;
  const std::size_t rhs_uncounted = add_resumed_counters(plan.manifest, done.size(), mc);
  const std::string status = mc.interrupted ? "interrupted" : rule->failed() ? "failed" : "complete";
  // The counters samples.csv does not hold, for a later --resume (steps are in its rows).
  plan.manifest["solver_counters"] = {{"samples", ran}, {"rhs_evals", mc.rhs_evals}};
  finish_manifest(plan, status, ran);

  json s;
  s["status"] = status;
  if (!mc.stop_reason.empty()) s["stop_reason"] = mc.stop_reason;
  s["study"] = {{"name", cfg.name}, {"title", cfg.title}, {"kind", cfg.kind}, {"file", cfg.file},
                {"model_file", cfg.model_path}, {"model_name", study.model_name()}, {"model_source", study.model_source()},
                {"notes", cfg.notes}, {"overrides", cfg.overrides}};
  s["sampling"] = {{"method", sampling::to_string(cfg.method)}, {"samples", ran}, {"planned_samples", n}, {"seed", seed},
                   {"threads", threads}, {"mpi_ranks", ranks}, {"replicate_size", cfg.replicate_size},
                   {"max_failure_share", cfg.max_failure_share}, {"inputs", study.input_names()},
                   {"ci_note", cfg.replicate_size > 0
                                   ? "95% intervals from the spread of the independent randomized replicates"
                                   : "95% intervals assume independent samples; for lhs and sobol designs they are "
                                     "conservative for the mean, not necessarily for tail quantiles (measured on the "
                                     "LOS study: replicate p99.73 interval wider than this one); [sampling] "
                                     "replicate_size gives honest intervals"}};
  json outputs;
  for (std::size_t k = 0; k < mc.outputs.size(); ++k) {
    json o = summary_json(mc.outputs[k]);
    o["unit"] = unit_of_output(study.output_names()[k]);
    outputs[study.output_names()[k]] = o;
  }
  s["outputs"] = outputs;
  // Declared reference figures (study and model files) beside the simulated distribution.
  std::vector<OutputSpec> specs;
  for (const auto& name : study.output_names()) specs.push_back({name, unit_of_output(name), ""});
  s["references"] = compare_references(declared_references(cfg, specs), specs, s["outputs"], [&](const std::string& name) {
    const auto& names = study.output_names();
    const auto it = std::find(names.begin(), names.end(), name);
    const auto k = static_cast<std::size_t>(it - names.begin());
    return it == names.end() || k >= mc.values.size() ? nullptr : &mc.values[k];
  });
  s["failures"] = failures_json(mc.failures, ran, mc.failed, seed, cfg.file);
  s["failures"]["by_reason"] = mc.failure_reasons;
  s["sample_convergence"] = convergence_json(study.output_names(), mc.outputs, ran, cfg.replicate_size, rule->until_json());
  if (sensitivity_base > 0 && status == "complete") {
    const auto names = study.design_dimension_names();
    std::vector<std::string> groups = names;
    if (cfg.saltelli_noise_group) {
      for (const auto& src : sources) groups.push_back("(within-sample randomness: " + src + ")");
    }
    // Every sample's value of output k (NaN where it failed), by sample index.
    std::vector<std::vector<double>> by_index(study.output_names().size(), std::vector<double>(ran, NAN));
    for (std::size_t k = 0; k < mc.values.size(); ++k) {
      for (std::size_t m = 0; m < mc.ok_index.size(); ++m) by_index[k][mc.ok_index[m]] = mc.values[k][m];
    }
    s["sensitivity"] = sensitivity_json(study.output_names(), groups, sensitivity_base, by_index, seed, tolerances);
  }
  s["solver"] = study.solver_json(mc);
  if (rhs_uncounted > 0) {
    s["solver"]["rhs_evals_note"] = "rhs_evals leaves out " + std::to_string(rhs_uncounted) +
                                    " samples of the first part of the run (it was stopped before it could record "
                                    "its counters in run.json)";
  }
  if (const json d = study.details(mc); !d.is_null()) s["details"] = d;
  s["provenance"] = {{"poise_version", kVersion}, {"git_commit", git_commit()},
                     {"study_file_sha1", file_sha1(cfg.file)}, {"model_file_sha1", file_sha1(cfg.model_path)},
                     {"seed", seed}, {"samples", ran}, {"threads", threads}, {"mpi_ranks", ranks},
                     {"wall_time_s", mc.wall_seconds},
                     {"started", started}, {"finished", now_iso8601()}, {"libraries", library_versions(options.plots && cfg.plots)},
                     {"resumed_after_sample", options.resume.empty() ? json(nullptr) : json(done.size())}};
  write_file_atomic((fs::path(dir) / "summary.json").string(), s.dump(2) + "\n");

  // Figures: the distribution of each main output (histogram and CDF with its band, the
  // declared references and requirements as lines) and its statistics against sample count.
  const fs::path pdir = fs::path(dir) / "plots";
  fs::create_directories(pdir);
  std::vector<std::string> figures;
  std::string plot_note;
  if (options.plots && cfg.plots && !mc.outputs.empty()) {
    for (const auto& name : main_outputs(study.output_names(), s["references"])) {
      const auto k = static_cast<std::size_t>(
          std::find(study.output_names().begin(), study.output_names().end(), name) - study.output_names().begin());
      if (k >= mc.values.size()) continue;
      std::vector<FigureLine> lines;
      for (const auto& c : s["references"]) {
        if (c["output"] == name) lines.push_back({c["reference"].get<double>(), c["name"].get<std::string>(),
                                                  c["role"] == "validation" ? "#cc3311" : "#999999"});
      }
      std::string why;
      if (!distribution_figures(pdir, name, unit_of_output(name), mc.values[k], mc.ok_index, lines, figures, why)) {
        plot_note = why;
      }
      if (s.contains("sensitivity") && !sensitivity_tornado(pdir, s["sensitivity"], name, figures, why)) plot_note = why;
    }
  }
  // Report.
  std::ostringstream h;
  h << report_page_head(cfg.name) << "<h1>"
    << html_escape(cfg.title.empty() ? cfg.name : cfg.title) << "</h1>\n<p>Study <code>" << html_escape(cfg.file) << "</code>, model <code>"
    << html_escape(cfg.model_path) << "</code> (" << html_escape(study.model_source()) << "). " << ran << " simulated samples ("
    << sampling::to_string(cfg.method) << ", seed " << seed << "), " << mc.failures << " failed.</p>\n";
  if (status != "complete") {
    h << "<p><b>This run is " << status << "</b>: " << html_escape(mc.stop_reason.empty() ? "stopped by a signal" : mc.stop_reason)
      << ". The figures below cover the " << ran << " samples that ran.</p>\n";
  }
  if (s.contains("sensitivity")) h << sensitivity_html(s["sensitivity"]);
  auto cell = [](const json& e) {
    std::string out = fmt(e["value"].get<double>(), 4) + " <small>[";
    out += e["ci95"][0].is_number() ? fmt(e["ci95"][0].get<double>(), 4) : std::string("&ndash;");
    out += ", ";
    out += e["ci95"][1].is_number() ? fmt(e["ci95"][1].get<double>(), 4) : std::string("&ndash;");
    return out + "]</small>";
  };
  h << references_html(s["references"]);
  study.report_sections(mc, pdir.string(), options.plots && cfg.plots, figures, h);
  h << "<h2>Outputs per sample</h2>\n<table><tr><th class='l'>output</th><th>mean</th><th>std</th><th>p50</th>"
       "<th>p95</th><th>p99.73</th><th>max</th></tr>\n";
  for (const auto& [name, o] : s["outputs"].items()) {
    h << "<tr><td class='l'><code>" << html_escape(name) << "</code> " << html_escape(o["unit"].get<std::string>()) << "</td><td>"
      << cell(o["mean"]) << "</td><td>" << cell(o["std"]) << "</td><td>" << cell(o["p50"]) << "</td><td>"
      << cell(o["p95"]) << "</td><td>" << cell(o["p99_73"]) << "</td><td>" << cell(o["max"]) << "</td></tr>\n";
  }
  h << "</table>\n" << convergence_html(s["sample_convergence"]) << "<h2>Figures</h2>\n";
  if (!plot_note.empty()) h << "<p>" << html_escape(plot_note) << "</p>\n";
  h << figures_html(pdir, figures);
  if (!cfg.notes.empty()) h << "<h2>Notes of the study</h2>\n<pre>" << html_escape(cfg.notes) << "</pre>\n";
  h << provenance_html(s["provenance"]) << "<h3>Solver</h3>\n<pre>" << html_escape(s["solver"].dump(2))
    << "</pre>\n</body></html>\n";
  write_file_atomic((fs::path(dir) / "report.html").string(), h.str());
  if (options.progress) std::fprintf(stderr, "poise: report %s\n", (fs::path(dir) / "report.html").c_str());
  finish_run_status(status, mc.stop_reason, mc.signal, ran, n, mc.failures, dir, cfg.file);
  return dir;
}

}  // namespace poise::studies
