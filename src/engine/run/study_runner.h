#pragma once
/// Runs a study file end to end and writes its result folder:
///   samples.csv   one row per sample: index, status, drawn inputs, outputs, message
///                 (streamed block by block, in sample order)
///   summary.json  statistics of every output with 95% CIs, the budget table, provenance
///   plots/        gnuplot scripts, data and SVG figures
///   report.html   the report a reviewer reads
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace poise::engine {

struct RunOptions {
  std::optional<std::size_t> samples;  ///< overrides [sampling] samples
  std::optional<std::uint64_t> seed;   ///< overrides [sampling] seed
  int threads = 0;                     ///< 0 = all hardware threads
  std::string out;                     ///< result folder; "" = results/<study>/<run id>
  std::string results_root = "results";
  bool progress = true;
  bool plots = true;  ///< false skips gnuplot (tests)
  /// Continue an interrupted run in this folder (gimbal studies): the samples already in
  /// its samples.csv are kept, the rest computed and appended. The study and model files
  /// must be unchanged (run.json holds their SHA-1); seed and sample count are the run's.
  std::string resume;
  /// "OUTPUT.STAT<=WIDTH[%]": run until that 95% interval is that narrow (convergence.h);
  /// the sample count is then the cap (max_samples, default 100 x the study's samples).
  std::string until;
  std::optional<std::size_t> max_samples;
  /// `poise run --require`: the study must state a requirement (else UsageError before the
  /// run); the command exits 3 unless every requirement is met.
  bool require = false;
  /// Keys set for this run on top of the study file's [overrides] (`poise run --set`,
  /// poise.run(overrides=...)): model keys ("yaw.bearing_span" = "70 mm") or study keys a
  /// kind lets an override set; summary.json records them with the study.
  std::map<std::string, std::string> overrides;
  /// > 0: `poise sensitivity`: Sobol indices from this many base rows (Saltelli layout).
  std::size_t sensitivity_base = 0;
};

/// A run stopped by SIGINT or SIGTERM after writing what it had done.
struct Interrupted : std::runtime_error {
  Interrupted(const std::string& what, int signal_number) : std::runtime_error(what), signal(signal_number) {}
  int signal;
};

/// Loads, validates (study and model), runs and writes the folder. Returns its path.
/// Throws ValidationError before anything runs if a file is invalid.
std::string run_study(const std::string& study_path, const RunOptions& options);

/// The study file a run folder's run.json records (for `poise run --resume DIR` without the
/// study path). Throws UsageError when DIR holds no run.json or it names no study file.
std::string study_file_of_run(const std::string& dir);

/// The answer of a finished run (its summary.json): the sentence and whether every
/// requirement is met (nullopt: none declared). Empty answer when the folder has none.
struct RunAnswer {
  std::string answer;
  std::optional<bool> met;
};
RunAnswer run_answer(const std::string& dir);

/// Validates a study and its model; returns a short human summary. Throws ValidationError.
std::string validate_study(const std::string& study_path);

/// Recomputes sample `index` alone and returns it as JSON (inputs, outputs, and the
/// pointing error at every grid point).
nlohmann::json replay_sample(const std::string& study_path, std::size_t index, const RunOptions& options);

}  // namespace poise::engine
