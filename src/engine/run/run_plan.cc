#include "engine/run/run_plan.h"
#include "core/diagnostics.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "core/error.h"
#include "core/version.h"
#include "engine/results/provenance.h"
#include "engine/results/result_io.h"
#include "sampling/distributed.h"

namespace poise::engine {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A resumed run's plan: its folder's run.json, refused when the study or model file changed.
void resume_plan(const StudyConfig& cfg, const std::string& dir, RunPlan& p) {
  p.dir = dir;
  std::ifstream mf(fs::path(p.dir) / "run.json");
  if (!mf) throw UsageError("--resume " + p.dir + ": no run.json there (not a run folder of Poise)");
  p.manifest = json::parse(mf, nullptr, false);
  if (p.manifest.is_discarded() || !p.manifest.is_object()) {
    throw UsageError("--resume " + p.dir + ": run.json is not valid JSON");
  }
  if (p.manifest.value("study_file_sha1", "") != file_sha1(cfg.file) ||
      p.manifest.value("model_file_sha1", "") != file_sha1(cfg.model_path)) {
    throw UsageError("--resume " + p.dir + ": the study or model file changed since the run began; start a new run");
  }
  p.samples = p.manifest.at("samples").get<std::size_t>();
  p.seed = p.manifest.at("seed").get<std::uint64_t>();
  p.until_text = p.manifest.value("until", "");
  p.sensitivity_base = p.manifest.value("sensitivity_base", std::size_t{0});
}

// The new run's folder, made by rank 0 ("" on the others); a refused --out (it holds a run) is
// every rank's error, so that none waits for a run that does not start.
std::string run_folder_on_root(const StudyConfig& cfg, const RunOptions& options) {
  std::string dir, refused;
  try {
    if (sampling::Cluster::root()) dir = make_run_folder(options.results_root, cfg.name, options.out);
  } catch (const UsageError& e) {
    refused = e.what();
  }
  refused = sampling::Cluster::broadcast(refused);
  if (!refused.empty()) throw UsageError(refused);
  return dir;
}

}  // namespace

RunPlan plan_run(StudyConfig& cfg, const RunOptions& options,
                 const std::function<std::pair<std::size_t, bool>()>& design_groups,
                 const std::function<std::vector<std::string>()>& output_names) {
  const bool root = sampling::Cluster::root();
  RunPlan p;
  p.samples = options.samples.value_or(cfg.samples);
  p.seed = options.seed.value_or(cfg.seed);
  p.until_text = options.until;
  p.sensitivity_base = options.sensitivity_base;
  p.threads = options.threads > 0 ? options.threads : sampling::Cluster::default_threads();
  if (p.samples == 0) throw UsageError("--samples must be at least 1");
  if (!options.resume.empty()) resume_plan(cfg, options.resume, p);
  // The sensitivity layout: base rows x (groups + 2) samples.
  if (p.sensitivity_base > 0) {
    const auto [dimensions, own_randomness] = design_groups();
    cfg.saltelli_base = p.sensitivity_base;
    cfg.saltelli_noise_group = own_randomness;
    cfg.replicate_size = 0;
    const std::size_t noise = own_randomness ? std::max<std::size_t>(cfg.saltelli_noise_sources, 1) : 0;
    p.samples = p.sensitivity_base * (dimensions + noise + cfg.saltelli_groups.size() + 2);
  } else {
    cfg.saltelli_groups.clear();
  }
  if (!p.until_text.empty()) {
    if (p.sensitivity_base > 0)
      throw UsageError("--until does not apply to a sensitivity run (its size is set by --base)");
    if (cfg.method != sampling::SamplingMethod::kMonteCarlo && cfg.replicate_size == 0) {
      throw UsageError(
          "--until needs samples that can grow: method = \"monte_carlo\", or lhs/sobol with [sampling] "
          "replicate_size (independent randomized replicates; an lhs or sobol design of N points is not "
          "the first N points of a larger one)");
    }
    if (options.resume.empty()) p.samples = options.max_samples.value_or(100 * cfg.samples);
    if (cfg.replicate_size > 0) {
      p.samples = std::max(cfg.replicate_size, p.samples / cfg.replicate_size * cfg.replicate_size);
    }
  }
  // A refused --until is refused before the result folder exists: a refused command
  // leaves nothing on disk.
  if (!p.until_text.empty()) check_until_design(parse_until(p.until_text, output_names()), cfg.replicate_size);
  if (options.resume.empty()) {
    p.dir = run_folder_on_root(cfg, options);
    p.manifest = {{"kind", cfg.kind},
                  {"study_file", fs::absolute(cfg.file).string()},
                  {"study_file_sha1", file_sha1(cfg.file)},
                  {"model_file_sha1", file_sha1(cfg.model_path)},
                  {"samples", p.samples},
                  {"seed", p.seed},
                  {"method", sampling::to_string(cfg.method)},
                  {"replicate_size", cfg.replicate_size},
                  {"until", p.until_text},
                  {"sensitivity_base", p.sensitivity_base},
                  {"poise_version", kVersion},
                  {"started", now_iso8601()},
                  {"status", "running"}};
    if (root) write_file_atomic((fs::path(p.dir) / "run.json").string(), p.manifest.dump(2) + "\n");
  }
  p.started = p.manifest.value("started", now_iso8601());
  return p;
}

std::string study_file_of_run(const std::string& dir) {
  const std::string path = (fs::path(dir) / "run.json").string();
  std::ifstream in(path);
  if (!in) throw UsageError("--resume " + dir + ": no run.json there (not a run folder of Poise)");
  const json manifest = json::parse(in, nullptr, false);
  if (manifest.is_discarded() || !manifest.is_object()) throw UsageError(path + ": not valid JSON");
  const auto it = manifest.find("study_file");
  if (it == manifest.end() || !it->is_string()) {
    throw UsageError(path +
                     " names no study file (a run begun by an older Poise): give it, "
                     "`poise run STUDY --resume " +
                     dir + "`");
  }
  return it->get<std::string>();
}

std::optional<UntilTarget> plan_until(const RunPlan& plan, const std::vector<std::string>& outputs) {
  if (plan.until_text.empty()) return std::nullopt;
  return parse_until(plan.until_text, outputs);
}

void announce_run(const StudyConfig& cfg, const RunPlan& plan, const std::optional<UntilTarget>& until, bool progress) {
  if (!progress || !sampling::Cluster::root()) return;
  const int ranks = sampling::Cluster::size();
  diagnostics::progress(
      "poise: study " + cfg.name + " -> " + plan.dir + "\n  " + std::to_string(plan.samples) + " samples" +
      (until ? " at most, until " + until->text : std::string()) + " (" + sampling::to_string(cfg.method) +
      (cfg.replicate_size > 0 ? ", replicates of " + std::to_string(cfg.replicate_size) : std::string()) + ", seed " +
      std::to_string(plan.seed) + ") on " + std::to_string(plan.threads) + " thread(s)" +
      (ranks > 1 ? " x " + std::to_string(ranks) + " MPI ranks" : std::string()));
}

std::string read_complete_rows(const std::string& csv_path, const std::string& header) {
  std::ifstream in(csv_path, std::ios::binary);
  if (!in) throw UsageError("--resume: cannot read " + csv_path);
  // In one read of the file's size (a character at a time took a tenth of a LOS resume).
  in.seekg(0, std::ios::end);
  std::string text(static_cast<std::size_t>(std::max<std::streamoff>(in.tellg(), 0)), '\0');
  in.seekg(0, std::ios::beg);
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  in.close();
  if (text.size() <= header.size() && header.compare(0, text.size(), text) == 0) {
    // A disk that filled up while the header was written: the header again, no rows yet.
    write_file_atomic(csv_path, header + "\n");
    return "";
  }
  const std::size_t complete = text.rfind('\n');
  if (complete == std::string::npos || text.compare(0, header.size() + 1, header + "\n") != 0) {
    throw UsageError("--resume: " + csv_path + " does not start with this study's header");
  }
  if (complete + 1 != text.size()) {  // cut the partial line an interruption left
    text.resize(complete + 1);
    write_file_atomic(csv_path, text);
  }
  return text.substr(header.size() + 1);
}

CheckedFile open_samples_csv(const RunPlan& plan, const std::string& header, bool resume) {
  if (!sampling::Cluster::root()) return {};
  CheckedFile csv((fs::path(plan.dir) / "samples.csv").string(), resume);
  if (!resume) csv.write(header + "\n");
  return csv;
}

void finish_manifest(RunPlan& plan, const std::string& status, std::size_t completed) {
  plan.manifest["status"] = status;
  plan.manifest["completed"] = completed;
  write_file_atomic((fs::path(plan.dir) / "run.json").string(), plan.manifest.dump(2) + "\n");
}

namespace {

// Sets "status": "failed" and the reason in a JSON file of the folder, if it is there and
// can still be written (a full disk may refuse even that: then it stays as it was).
void mark_failed(const fs::path& file, const std::string& reason) {
  std::error_code ec;
  if (!fs::exists(file, ec)) return;
  try {
    std::ifstream in(file);
    json j = json::parse(in, nullptr, false);
    in.close();
    if (j.is_discarded() || !j.is_object()) return;
    j["status"] = "failed";
    j["stop_reason"] = reason;
    write_file_atomic(file.string(), j.dump(2) + "\n");
  } catch (const std::exception&) {
  }
}

}  // namespace

std::string record_write_failure(const std::string& failed_file, const std::string& reason) {
  std::error_code ec;
  fs::path dir = fs::path(failed_file).parent_path();
  for (int up = 0; up < 2 && !dir.empty(); ++up, dir = dir.parent_path()) {
    if (fs::exists(dir / "run.json", ec) || fs::exists(dir / "samples.csv", ec)) {
      mark_failed(dir / "run.json", reason);
      mark_failed(dir / "summary.json", reason);
      return dir.string();
    }
  }
  return "";
}

}  // namespace poise::engine
