#include "cli/study_commands.h"

#include <iostream>

#include "cli/count_check.h"
#include "core/error.h"
#include "engine/kind_interface/programs_allowed.h"
#include "engine/study_files/toml_reader.h"
#include "sampling/distributed.h"

namespace poise::cli {

StudyCommands::StudyCommands(CLI::App& app) {
  add_run(app);
  add_sensitivity(app);
  validate_ = app.add_subcommand("validate", "check a study file and its model file; run nothing");
  validate_->add_option("STUDY", study_, "study file (TOML)")->required()->check(CLI::ExistingFile);
  replay_ = app.add_subcommand("replay", "recompute one sample alone and print it as JSON");
  add_common(replay_, false);
  replay_->add_option("--sample,-i", index_, "sample index (0-based, as in samples.csv)")->required();
}

void StudyCommands::add_common(CLI::App* sub, bool resumable) {
  CLI::Option* file = sub->add_option(
      "STUDY", study_,
      resumable ? "study file (TOML), e.g. studies/los_seeker_wang2011.toml; with --resume, run.json names it"
                : "study file (TOML), e.g. studies/los_seeker_wang2011.toml");
  file->check(CLI::ExistingFile);
  if (!resumable) file->required();
  sub->add_option("--samples,-n", samples_, "number of samples (overrides [sampling] samples)")->check(at_least_one());
  sub->add_option("--seed,-s", seed_, "random seed (overrides [sampling] seed); same seed, same samples");
  add_allow_programs(sub);
}

void StudyCommands::add_allow_programs(CLI::App* sub) {
  sub->add_flag("--allow-programs", allow_programs_,
                "start the program a model file names (kind = \"external\"); without it such a study is refused: "
                "only for a program you trust");
}

void StudyCommands::add_run(CLI::App& app) {
  run_ = app.add_subcommand("run", "validate a study, run it and write its result folder");
  add_common(run_, true);
  run_->add_option("--threads,-j", opt_.threads, "worker threads (default: all cores); results do not depend on it")
      ->check(CLI::NonNegativeNumber);
  run_->add_option("--out,-o", opt_.out, "result folder (default results/<study>/<run id>); must not hold a run");
  run_->add_option("--results-root", opt_.results_root, "where default result folders go (default: results)");
  run_->add_option("--resume", opt_.resume,
                   "continue an interrupted run in this folder: keeps its samples.csv rows, "
                   "computes the rest (same seed and sample count; the study files must be unchanged)")
      ->excludes("--out")
      ->excludes("--samples")
      ->excludes("--seed");
  run_->add_option("--until", opt_.until,
                   "run until a 95% interval is this narrow: OUTPUT.STAT<=WIDTH (STAT: mean, std, p0_135, p2_5, p50, "
                   "p95, p97_5, "
                   "p99_73, p99_865; "
                   "WIDTH in the output's unit, or N% of the figure), e.g. \"los_max_arcsec.p95<=0.2\". Checked at "
                   "~10% steps of the sample count; needs monte_carlo, or lhs/sobol with [sampling] replicate_size")
      ->excludes("--resume")
      ->excludes("--samples");
  run_->add_option("--max-samples", max_samples_, "cap of an --until run (default 100 x the study's samples)")
      ->needs("--until")
      ->check(at_least_one());
  run_->add_option("--set", settings_,
                   "KEY=VALUE: set a model key (or a study key the kind allows) for this run on top of the study "
                   "file's [overrides], e.g. --set \"yaw.bearing_span=70 mm\"; repeat for more keys")
      ->excludes("--resume");
  run_->add_flag("--quiet,-q", quiet_, "no progress on stderr");
  run_->add_flag("--no-plots", no_plots_, "skip gnuplot figures");
  run_->add_flag("--require", opt_.require,
                 "for nightly and CI use: exit 3 unless every [[requirement]] of the study is met (not met or "
                 "undecided: 3); a study without requirements is refused (exit 2). Without it a completed run exits 0 "
                 "whatever its verdicts");
}

void StudyCommands::add_sensitivity(CLI::App& app) {
  sensitivity_ = app.add_subcommand(
      "sensitivity",
      "Sobol indices: which tolerance drives each output. Runs the study on the Saltelli layout: base rows of two "
      "independent designs A and B and, per input, A with that input from B (base x (inputs + 2) samples, plus one "
      "group for a procedure's own randomness such as noise); first-order (Saltelli 2010) and total (Jansen 1999) "
      "indices with 95% bootstrap intervals in summary.json \"sensitivity\" and report.html. Resumable like a run "
      "(--resume), and distributed under mpirun.");
  CLI::App* s = sensitivity_;
  s->add_option("STUDY", study_, "study file (TOML); with --resume, run.json names it")->check(CLI::ExistingFile);
  add_allow_programs(s);
  s->add_option("--base,-b", base_,
                "base rows N (each index's interval narrows as 1/sqrt(N); 64-256 for a "
                "simulated procedure, 1000+ for a LOS study)")
      ->check(at_least_one());
  s->add_option("--seed,-s", seed_, "random seed (overrides [sampling] seed)");
  s->add_option("--threads,-j", opt_.threads, "worker threads (default: all cores)")->check(CLI::NonNegativeNumber);
  s->add_option("--out,-o", opt_.out, "result folder (default results/<study>/<run id>)");
  s->add_option("--results-root", opt_.results_root, "where default result folders go (default: results)");
  s->add_option("--resume", opt_.resume, "continue an interrupted sensitivity run in this folder")->excludes("--out");
  s->add_flag("--quiet,-q", quiet_, "no progress on stderr");
  s->add_flag("--no-plots", no_plots_, "skip gnuplot figures");
}

std::optional<int> StudyCommands::settle_options() {
  if (distributes() && study_.empty()) {
    if (opt_.resume.empty()) {
      std::cerr << "poise: STUDY is required (the study file), or --resume DIR to continue a run\n";
      return 2;
    }
    try {
      study_ = engine::study_file_of_run(opt_.resume);
    } catch (const std::exception& e) {
      std::cerr << "poise: " << e.what() << "\nNothing was run.\n";
      return 2;
    }
  }
  for (const auto& setting : settings_) {
    const auto eq = setting.find('=');
    if (eq == std::string::npos || eq == 0) {
      std::cerr << "poise run: --set '" << setting << "': expected KEY=VALUE, e.g. --set \"yaw.bearing_span=70 mm\"\n";
      return 2;
    }
    opt_.overrides[setting.substr(0, eq)] = setting.substr(eq + 1);
  }
  if (samples_ > 0) opt_.samples = samples_;
  if (max_samples_ > 0) opt_.max_samples = max_samples_;
  if (*sensitivity_) {
    if (base_ == 0 && opt_.resume.empty()) {
      std::cerr << "poise sensitivity: --base N is required (base rows of the Saltelli layout)\n";
      return 2;
    }
    opt_.sensitivity_base = base_;
    if (sensitivity_->count("--seed")) opt_.seed = seed_;
  }
  if (run_->count("--seed") || replay_->count("--seed")) opt_.seed = seed_;
  opt_.progress = !quiet_;
  opt_.plots = !no_plots_;
  return std::nullopt;
}

int StudyCommands::execute() {
  const bool root = sampling::Cluster::root();
  if (allow_programs_) engine::allow_programs(true);
  try {
    if (*validate_) {
      std::cout << engine::validate_study(study_) << '\n';
    } else if (distributes()) {
      const std::string dir = engine::run_study(study_, opt_);
      if (root) {
        // The answer is the last line before the report's path: the sentence summary.json
        // and the report open with.
        const engine::RunAnswer answer = engine::run_answer(dir);
        if (!answer.answer.empty()) std::cout << answer.answer << '\n';
        std::cout << "report: " << dir << "/report.html\n";
        if (opt_.require && answer.met != true) return 3;
      }
    } else if (*replay_) {
      std::cout << engine::replay_sample(study_, index_, opt_).dump(2) << '\n';
    }
  } catch (const engine::ValidationError& e) {
    if (root) std::cerr << "poise: " << e.what() << "\nNothing was run.\n";
    return 2;
  } catch (const UsageError& e) {
    if (root) std::cerr << "poise: " << e.what() << "\nNothing was run.\n";
    return 2;
  } catch (const engine::Interrupted& e) {
    if (root) std::cerr << "\npoise: " << e.what() << '\n';
    return 128 + e.signal;
  } catch (const std::exception& e) {
    std::cerr << "poise: error: " << e.what() << '\n';
    return 1;
  }
  return 0;
}

std::optional<int> StudyCommands::operator()() {
  if (!distributes() && !*validate_ && !*replay_) return std::nullopt;
  if (const auto refused = settle_options()) return refused;
  return execute();
}

}  // namespace poise::cli
