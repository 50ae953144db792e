#pragma once
/// The commands on a study file: `poise run`, `sensitivity`, `validate` and `replay`: their
/// options (added to the app at construction) and, once parsed, the run that prints the answer
/// as the last line before the report's path. Construct in place (CLI11 binds to its members).
#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/run/study_runner.h"

namespace poise::cli {

class StudyCommands {
 public:
  explicit StudyCommands(CLI::App& app);
  StudyCommands(const StudyCommands&) = delete;
  StudyCommands& operator=(const StudyCommands&) = delete;

  /// Whether the parsed command spreads its samples over MPI ranks (run, sensitivity).
  bool distributes() const { return *run_ || *sensitivity_; }
  /// Runs the parsed study command; nothing if another command was parsed. Exit status:
  /// 0 done, 1 failed, 2 refused input, 3 a --require run not met, 128 + signal interrupted.
  std::optional<int> operator()();

 private:
  void add_common(CLI::App* sub, bool resumable);
  void add_run(CLI::App& app);
  void add_sensitivity(CLI::App& app);
  void add_allow_programs(CLI::App* sub);
  /// The parsed options into `opt_` (study from --resume, --set, seeds); a refusal's status.
  std::optional<int> settle_options();
  int execute();

  engine::RunOptions opt_;
  std::string study_;
  std::size_t samples_ = 0, max_samples_ = 0, base_ = 0, index_ = 0;
  std::uint64_t seed_ = 0;
  bool quiet_ = false, no_plots_ = false, allow_programs_ = false;
  std::vector<std::string> settings_;
  CLI::App* run_ = nullptr;
  CLI::App* sensitivity_ = nullptr;
  CLI::App* validate_ = nullptr;
  CLI::App* replay_ = nullptr;
};

}  // namespace poise::cli
