#include "engine/run_plan.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "core/error.h"
#include "core/version.h"
#include "sampling/distributed.h"
#include "engine/provenance.h"
#include "engine/result_io.h"

namespace poise::studies {
namespace fs = std::filesystem;
using nlohmann::json;

RunPlan plan_run(StudyConfig& cfg, const RunOptions& options,
                 const std::function<std::pair<std::size_t, bool>()>& design_groups) {
  const bool root = sampling::Cluster::root();
  RunPlan p;
  p.samples = options.samples.value_or(cfg.samples);
  p.seed = options.seed.value_or(cfg.seed);
  p.until_text = options.until;
  p.sensitivity_base = options.sensitivity_base;
  p.threads = options.threads > 0 ? options.threads
                                  : std::max(1, static_cast<int>(std::max(1u, std::thread::hardware_concurrency())) /
                                                    std::max(1, sampling::Cluster::local_size()));
  if (p.samples == 0) throw Error("--samples must be at least 1");
  if (!options.resume.empty()) {
    p.dir = options.resume;
    std::ifstream mf(fs::path(p.dir) / "run.json");
    if (!mf) throw Error("--resume " + p.dir + ": no run.json there (not a run folder of Poise)");
    p.manifest = json::parse(mf);
    if (p.manifest.value("study_file_sha1", "") != file_sha1(cfg.file) ||
        p.manifest.value("model_file_sha1", "") != file_sha1(cfg.model_path)) {
      throw Error("--resume " + p.dir + ": the study or model file changed since the run began; start a new run");
    }
    p.samples = p.manifest.at("samples").get<std::size_t>();
    p.seed = p.manifest.at("seed").get<std::uint64_t>();
    p.until_text = p.manifest.value("until", "");
    p.sensitivity_base = p.manifest.value("sensitivity_base", std::size_t{0});
  }
  // The sensitivity layout: base rows x (groups + 2) samples.
  if (p.sensitivity_base > 0) {
    const auto [dimensions, own_randomness] = design_groups();
    cfg.saltelli_base = p.sensitivity_base;
    cfg.saltelli_noise_group = own_randomness;
    cfg.replicate_size = 0;
    p.samples = p.sensitivity_base * (dimensions + (own_randomness ? 1 : 0) + 2);
  }
  if (!p.until_text.empty()) {
    if (p.sensitivity_base > 0) throw Error("--until does not apply to a sensitivity run (its size is set by --base)");
    if (cfg.method != sampling::SamplingMethod::kMonteCarlo && cfg.replicate_size == 0) {
      throw Error("--until needs samples that can grow: method = \"monte_carlo\", or lhs/sobol with [sampling] "
                  "replicate_size (independent randomized replicates; an lhs or sobol design of N points is not "
                  "the first N points of a larger one)");
    }
    if (options.resume.empty()) p.samples = options.max_samples.value_or(100 * cfg.samples);
    if (cfg.replicate_size > 0) {
      p.samples = std::max(cfg.replicate_size, p.samples / cfg.replicate_size * cfg.replicate_size);
    }
  }
  if (options.resume.empty()) {
    if (root) p.dir = make_run_folder(options.results_root, cfg.name, options.out);
    p.manifest = {{"kind", cfg.kind}, {"study_file_sha1", file_sha1(cfg.file)},
                  {"model_file_sha1", file_sha1(cfg.model_path)}, {"samples", p.samples}, {"seed", p.seed},
                  {"method", sampling::to_string(cfg.method)}, {"replicate_size", cfg.replicate_size},
                  {"until", p.until_text}, {"sensitivity_base", p.sensitivity_base},
                  {"poise_version", kVersion}, {"started", now_iso8601()}, {"status", "running"}};
    if (root) write_file_atomic((fs::path(p.dir) / "run.json").string(), p.manifest.dump(2) + "\n");
  }
  p.started = p.manifest.value("started", now_iso8601());
  return p;
}

std::optional<UntilTarget> plan_until(const RunPlan& plan, const std::vector<std::string>& outputs) {
  if (plan.until_text.empty()) return std::nullopt;
  return parse_until(plan.until_text, outputs);
}

void announce_run(const StudyConfig& cfg, const RunPlan& plan, const std::optional<UntilTarget>& until, bool progress) {
  if (!progress || !sampling::Cluster::root()) return;
  const int ranks = sampling::Cluster::size();
  std::fprintf(stderr, "poise: study %s -> %s\n  %zu samples%s (%s%s, seed %llu) on %d thread(s)%s\n", cfg.name.c_str(),
               plan.dir.c_str(), plan.samples, until ? (" at most, until " + until->text).c_str() : "",
               sampling::to_string(cfg.method).c_str(),
               cfg.replicate_size > 0 ? (", replicates of " + std::to_string(cfg.replicate_size)).c_str() : "",
               static_cast<unsigned long long>(plan.seed), plan.threads,
               ranks > 1 ? (" x " + std::to_string(ranks) + " MPI ranks").c_str() : "");
}

std::string read_complete_rows(const std::string& csv_path, const std::string& header) {
  std::ifstream in(csv_path, std::ios::binary);
  if (!in) throw Error("--resume: cannot read " + csv_path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const std::size_t complete = text.rfind('\n');
  if (complete == std::string::npos || text.compare(0, header.size() + 1, header + "\n") != 0) {
    throw Error("--resume: " + csv_path + " does not start with this study's header");
  }
  if (complete + 1 != text.size()) {  // cut the partial line an interruption left
    text.resize(complete + 1);
    write_file_atomic(csv_path, text);
  }
  return text.substr(header.size() + 1);
}

std::ofstream open_samples_csv(const RunPlan& plan, const std::string& header, bool resume) {
  std::ofstream csv;
  if (!sampling::Cluster::root()) return csv;
  const std::string path = (fs::path(plan.dir) / "samples.csv").string();
  csv.open(path, resume ? std::ios::app : std::ios::trunc);
  if (!csv) throw Error("cannot write " + path);
  if (!resume) csv << header << '\n' << std::flush;
  return csv;
}

void finish_manifest(RunPlan& plan, const std::string& status, std::size_t completed) {
  plan.manifest["status"] = status;
  plan.manifest["completed"] = completed;
  write_file_atomic((fs::path(plan.dir) / "run.json").string(), plan.manifest.dump(2) + "\n");
}

}  // namespace poise::studies
