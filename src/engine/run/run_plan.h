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

#include "engine/results/checked_file.h"
#include "engine/run/convergence.h"
#include "engine/run/study_runner.h"
#include "engine/study_files/study_config.h"

namespace poise::engine {

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
/// randomness of their own); `output_names()` lists the study's outputs (an --until target is checked against them
/// before the folder is made). Throws UsageError on a folder that cannot be resumed or an
/// --until that cannot apply, and creates nothing then.
RunPlan plan_run(StudyConfig& cfg, const RunOptions& options,
                 const std::function<std::pair<std::size_t, bool>()>& design_groups,
                 const std::function<std::vector<std::string>()>& output_names);

/// The --until target of a plan (parsed against the study's outputs), if any.
std::optional<UntilTarget> plan_until(const RunPlan& plan, const std::vector<std::string>& outputs);

/// Prints the run's first progress lines (rank 0, when progress is on).
void announce_run(const StudyConfig& cfg, const RunPlan& plan, const std::optional<UntilTarget>& until, bool progress);

/// The complete rows of an interrupted run's samples.csv (text after the header line); a
/// partial last line an interruption left is cut off the file. Throws if the header is not
/// this study's.
std::string read_complete_rows(const std::string& csv_path, const std::string& header);

/// samples.csv of the run on rank 0 (a closed file elsewhere): a new file with its header,
/// or a resumed run's, to append to. Every write is checked (WriteError).
CheckedFile open_samples_csv(const RunPlan& plan, const std::string& header, bool resume);

/// Records the run's end in run.json: status and completed samples (rank 0).
void finish_manifest(RunPlan& plan, const std::string& status, std::size_t completed);

/// After a write the system refused (WriteError on `failed_file`): the run folder holding it
/// (found beside it or one level up) gets "status": "failed" and the reason in run.json and
/// summary.json where they exist and can still be written. Returns the folder ("" if none).
std::string record_write_failure(const std::string& failed_file, const std::string& reason);

}  // namespace poise::engine
