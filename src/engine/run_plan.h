#pragma once
/// The plan of a run, shared by every runner that streams samples (seeker, gimbal,
/// balancing machine, platform): its folder and run.json (new, or a resumed run's, checked
/// against the study and model files), sample count, seed, --until target, sensitivity
/// layout and threads. run.json is written atomically, with the run's status.
#include <cstdint>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/convergence.h"
#include "engine/study_config.h"
#include "engine/study_runner.h"

namespace poise::studies {

struct RunPlan {
  std::string dir;  ///< "" on MPI ranks other than 0 (they write nothing)
  nlohmann::json manifest;
  std::size_t samples = 0;
  std::uint64_t seed = 0;
  std::string until_text;
  std::size_t sensitivity_base = 0;
  int threads = 1;  ///< this process's (default: the machine's cores shared among its ranks)
  std::string started;
};

/// Plans the run of `cfg` (which it sets up for the sensitivity layout when asked:
/// `design_groups()` returns the study's design dimensions and whether its samples have
/// randomness of their own). Throws Error on a folder that cannot be resumed or an --until
/// that cannot apply.
RunPlan plan_run(StudyConfig& cfg, const RunOptions& options,
                 const std::function<std::pair<std::size_t, bool>()>& design_groups);

/// The --until target of a plan (parsed against the study's outputs), if any.
std::optional<UntilTarget> plan_until(const RunPlan& plan, const std::vector<std::string>& outputs);

/// Prints the run's first progress lines (rank 0, when progress is on).
void announce_run(const StudyConfig& cfg, const RunPlan& plan, const std::optional<UntilTarget>& until, bool progress);

/// The complete rows of an interrupted run's samples.csv (text after the header line); a
/// partial last line an interruption left is cut off the file. Throws if the header is not
/// this study's.
std::string read_complete_rows(const std::string& csv_path, const std::string& header);

/// samples.csv of the run on rank 0 (a closed stream elsewhere): a new file with its header,
/// or a resumed run's, to append to.
std::ofstream open_samples_csv(const RunPlan& plan, const std::string& header, bool resume);

/// Records the run's end in run.json: status and completed samples (rank 0).
void finish_manifest(RunPlan& plan, const std::string& status, std::size_t completed);

}  // namespace poise::studies
