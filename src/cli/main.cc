// poise: command-line entry point. See `poise --help`.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <thread>
#include <iostream>
#include <string>
#include <vector>

#include "cli/budget_command.h"
#include "cli/count_check.h"
#include "cli/diagnose_command.h"
#include "cli/error_mechanisms_command.h"
#include "cli/fit_command.h"
#include "cli/keys_command.h"
#include "cli/mass_properties_command.h"
#include "cli/optimize_command.h"
#include "cli/record_command.h"
#include "core/error.h"
#include "core/version.h"
#include "sampling/distributed.h"
#include "engine/run/study_runner.h"
#include "engine/study_files/toml_reader.h"
#include "kinds/registry.h"

namespace {

const char* kDescription = R"(Poise: Monte Carlo tolerance analysis of precision gimbals and balancing machines.

A study file (TOML) names a model file, how to sample its tolerances and what to report.
Every value carries its unit ("0.004 mm", "82 mm", "30 deg", "4 arcsec"); unknown keys,
missing units and non-physical values are refused with file, line, key and what was expected.

Study kinds (each a module; `poise keys KIND` lists its study and model keys):
%KINDS%
Examples:
  poise validate studies/los_seeker_wang2011.toml
  poise run studies/los_seeker_wang2011.toml
  poise run studies/yang2015_repeatability.toml --samples 8
  poise run studies/wang2014_umar.toml
  poise fit data/yang2015/table1_loading_test_36pt.csv --json
  poise error-mechanisms data/yang2015
      which per-test error (K_T scale and zero, or additive) the measured tests support
  poise mass-properties rotor_disk.stl --unit mm --density "2700 kg/m^3"
  poise run studies/los_seeker_wang2011.toml --samples 100000 --seed 7 --threads 2 --out /tmp/los
  poise run --resume /tmp/los
  poise replay studies/los_seeker_wang2011.toml --sample 42
  poise optimize studies/bearing_span_sizing.toml
  poise budget studies/wang2011_budget.toml --out /tmp/budget
      a reviewer's error budget: every line recomputed from its inputs, verdicts and likely
      slips, the combined figure at the requirement's confidence, the Monte Carlo beside it

A run writes results/<study>/<run id>/ (never overwriting an earlier run): samples.csv,
samples.h5, summary.json (statistics with 95% confidence intervals, provenance), plots/ and
report.html. A study answers its question: each [[requirement]] (output, statistic,
at_most or at_least, confidence) gets a verdict (met, not met, undecided) on the statistic's
one-sided bound, and one sentence, summary.json "answer", says whether every requirement is
met; the report opens with it and `poise run` prints it last, before the report's path:
  poise run studies/gimbal_unbalance_mc.toml --require
      exit 3 unless every requirement is met (nightly and CI)

Long runs: samples stream to samples.csv as they finish. Ctrl-C (SIGINT) or SIGTERM stops
after the block in flight and writes the summary of what was done; a second Ctrl-C, or
kill -9, ends at once, and every finished sample stays on disk either way. Complete the run
with `poise run --resume DIR` (run.json names the study file): the result equals an uninterrupted run's. summary.json,
run.json and report.html are written atomically (never half a file).
  poise run studies/los_seeker_wang2011_replicates.toml --until "los_max_arcsec.p95<=0.2"
      sample until the 95% interval of p95 is 0.2 arcsec wide (Monte Carlo, or lhs/sobol
      with [sampling] replicate_size: independent randomized replicates, intervals by replicate;
      a quantile needs replicates with 10 or more samples beyond it: 200 for p95, 3704 for p99.73)
  poise sensitivity studies/gimbal_unbalance_mc.toml --base 64
      Sobol first-order and total indices of every output with bootstrap intervals: which
      tolerance drives which output
  mpirun -np 4 build/poise run studies/yang2015_repeatability.toml
      the samples split over 4 MPI ranks (built with Open MPI); same samples.csv and
      statistics as one process. A sample that fails is kept with its reason; the run stops
      with an error once more than [sampling] max_failure_share (default 0.05) of it failed.

Exit status, the same for every command:
  0        success
  2        invalid input or command line: a study, model or data file refused, an unknown
           option, a value out of range, --out into a folder that holds a run, a sample index
           past the run's end; nothing ran and nothing was created
  1        a run that failed: too many failed samples, a disk full or another failed write
           (the message names the file and the system's reason; run.json says "failed";
           `poise run --resume DIR` continues once the cause is fixed)
  128 + N  stopped by signal N (130 for SIGINT, 143 for SIGTERM); resumable
  3        `poise run --require`: a requirement of the study is not met or undecided;
           `poise optimize`: the best design found was not verified)";

}  // namespace

int run_main(int argc, char** argv);

int main(int argc, char** argv) {
  poise::kinds::register_study_kinds();
  try {
    poise::sampling::Cluster::init(&argc, &argv);
  } catch (const std::exception& e) {
    std::cerr << "poise: error: " << e.what() << '\n';
    return 1;
  }
  int status = 1;
  try {
    status = run_main(argc, argv);
  } catch (const std::exception& e) {  // the last guard: nothing leaves Poise as an abort
    std::cerr << "poise: error: " << e.what() << '\n';
  } catch (...) {
    std::cerr << "poise: error: an unknown exception\n";
  }
  if (status == 1 && poise::sampling::Cluster::size() > 1) {
    // An error on one rank (rank 0 writing the folder, say) must not leave the others
    // waiting for it: end them all, after rank 0 had a moment to print why.
    if (!poise::sampling::Cluster::root()) std::this_thread::sleep_for(std::chrono::seconds(1));
    poise::sampling::Cluster::abort(status);
  }
  poise::sampling::Cluster::finalize();
  return status;
}

int run_main(int argc, char** argv) {
  // What Poise is, then the usage, the options and the commands; the study kinds, examples,
  // result folder, long runs and exit statuses after them (the footer): usage comes first.
  std::string text = kDescription;
  text.replace(text.find("%KINDS%"), 7, poise::cli::study_kinds_text());
  const std::size_t kinds_at = text.find("Study kinds (");
  CLI::App app{text.substr(0, kinds_at), "poise"};
  app.footer("\n" + text.substr(kinds_at));
  app.set_version_flag("--version", std::string("poise ") + poise::kVersion + " (" + poise::kGitCommit + ")");
  app.require_subcommand(1);

  poise::engine::RunOptions opt;
  std::string study;
  std::size_t samples = 0;
  std::uint64_t seed = 0;
  bool quiet = false, no_plots = false;

  auto add_common = [&](CLI::App* sub, bool resumable) {
    CLI::Option* file = sub->add_option(
        "STUDY", study,
        resumable ? "study file (TOML), e.g. studies/los_seeker_wang2011.toml; with --resume, run.json names it"
                  : "study file (TOML), e.g. studies/los_seeker_wang2011.toml");
    file->check(CLI::ExistingFile);
    if (!resumable) file->required();
    sub->add_option("--samples,-n", samples, "number of samples (overrides [sampling] samples)")
        ->check(poise::cli::at_least_one());
    sub->add_option("--seed,-s", seed, "random seed (overrides [sampling] seed); same seed, same samples");
  };

  CLI::App* run = app.add_subcommand("run", "validate a study, run it and write its result folder");
  add_common(run, true);
  run->add_option("--threads,-j", opt.threads,
                  "worker threads (default: all cores); results do not depend on it")
      ->check(CLI::NonNegativeNumber);
  run->add_option("--out,-o", opt.out, "result folder (default results/<study>/<run id>); must not hold a run");
  run->add_option("--results-root", opt.results_root, "where default result folders go (default: results)");
  run->add_option("--resume", opt.resume,
                  "continue an interrupted run in this folder: keeps its samples.csv rows, "
                  "computes the rest (same seed and sample count; the study files must be unchanged)")
      ->excludes("--out")
      ->excludes("--samples")
      ->excludes("--seed");
  run->add_option("--until", opt.until,
                  "run until a 95% interval is this narrow: OUTPUT.STAT<=WIDTH (STAT: mean, std, p50, p95, p99_73; "
                  "WIDTH in the output's unit, or N% of the figure), e.g. \"los_max_arcsec.p95<=0.2\". Checked at "
                  "~10% steps of the sample count; needs monte_carlo, or lhs/sobol with [sampling] replicate_size")
      ->excludes("--resume")
      ->excludes("--samples");
  std::size_t max_samples = 0;
  run->add_option("--max-samples", max_samples, "cap of an --until run (default 100 x the study's samples)")
      ->needs("--until")
      ->check(poise::cli::at_least_one());
  std::vector<std::string> settings;
  run->add_option("--set", settings,
                  "KEY=VALUE: set a model key (or a study key the kind allows) for this run on top of the study "
                  "file's [overrides], e.g. --set \"yaw.bearing_span=70 mm\"; repeat for more keys")
      ->excludes("--resume");
  run->add_flag("--quiet,-q", quiet, "no progress on stderr");
  run->add_flag("--no-plots", no_plots, "skip gnuplot figures");
  run->add_flag("--require", opt.require,
                "for nightly and CI use: exit 3 unless every [[requirement]] of the study is met (not met or "
                "undecided: 3); a study without requirements is refused (exit 2). Without it a completed run exits 0 "
                "whatever its verdicts");

  CLI::App* sens = app.add_subcommand(
      "sensitivity",
      "Sobol indices: which tolerance drives each output. Runs the study on the Saltelli layout: base rows of two "
      "independent designs A and B and, per input, A with that input from B (base x (inputs + 2) samples, plus one "
      "group for a procedure's own randomness such as noise); first-order (Saltelli 2010) and total (Jansen 1999) "
      "indices with 95% bootstrap intervals in summary.json \"sensitivity\" and report.html. Resumable like a run "
      "(--resume), and distributed under mpirun.");
  std::size_t base = 0;
  sens->add_option("STUDY", study, "study file (TOML); with --resume, run.json names it")->check(CLI::ExistingFile);
  sens->add_option("--base,-b", base, "base rows N (each index's interval narrows as 1/sqrt(N); 64-256 for a "
                                      "simulated procedure, 1000+ for a LOS study)")
      ->check(poise::cli::at_least_one());
  sens->add_option("--seed,-s", seed, "random seed (overrides [sampling] seed)");
  sens->add_option("--threads,-j", opt.threads, "worker threads (default: all cores)")->check(CLI::NonNegativeNumber);
  sens->add_option("--out,-o", opt.out, "result folder (default results/<study>/<run id>)");
  sens->add_option("--results-root", opt.results_root, "where default result folders go (default: results)");
  sens->add_option("--resume", opt.resume, "continue an interrupted sensitivity run in this folder")->excludes("--out");
  sens->add_flag("--quiet,-q", quiet, "no progress on stderr");
  sens->add_flag("--no-plots", no_plots, "skip gnuplot figures");

  CLI::App* validate = app.add_subcommand("validate", "check a study file and its model file; run nothing");
  validate->add_option("STUDY", study, "study file (TOML)")->required()->check(CLI::ExistingFile);

  std::size_t index = 0;
  CLI::App* replay = app.add_subcommand("replay", "recompute one sample alone and print it as JSON");
  add_common(replay, false);
  replay->add_option("--sample,-i", index, "sample index (0-based, as in samples.csv)")->required();

  const poise::cli::FitHandler fit = poise::cli::add_fit_command(app);
  const poise::cli::ErrorMechanismsHandler mechanisms = poise::cli::add_error_mechanisms_command(app);
  const poise::cli::DiagnoseHandler diagnose = poise::cli::add_diagnose_command(app);
  const auto record = poise::cli::add_record_commands(app);
  const poise::cli::OptimizeHandler optimize = poise::cli::add_optimize_command(app);
  const poise::cli::KeysHandler keys = poise::cli::add_keys_command(app);
  const poise::cli::BudgetHandler budget = poise::cli::add_budget_command(app);
  const poise::cli::MassPropertiesHandler mass_properties = poise::cli::add_mass_properties_command(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);  // 0
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints CLI11's message and "Run with --help for more information."
    return 2;     // a command-line mistake is invalid input, whatever CLI11's own code
  }
  if (poise::sampling::Cluster::size() > 1 && !*run && !*sens) {
    if (poise::sampling::Cluster::root()) {
      std::cerr << "poise: under mpirun only `poise run` and `poise sensitivity` distribute their samples; run "
                   "this command in one process\n";
    }
    return 2;
  }
  // Every command's exceptions end here: refused input 2, an interruption 128 + signal,
  // any other failure 1, each with its message (the commands catch what they can name).
  try {
    if (const auto status = fit()) return *status;
    if (const auto status = mechanisms()) return *status;
    if (const auto status = diagnose()) return *status;
    if (const auto status = record()) return *status;
    if (const auto status = optimize()) return *status;
    if (const auto status = keys()) return *status;
    if (const auto status = budget()) return *status;
    if (const auto status = mass_properties()) return *status;
  } catch (const poise::UsageError& e) {
    std::cerr << "poise: " << e.what() << "\nNothing was run.\n";
    return 2;
  } catch (const poise::engine::ValidationError& e) {
    std::cerr << "poise: " << e.what() << "\nNothing was run.\n";
    return 2;
  } catch (const poise::engine::Interrupted& e) {
    std::cerr << "\npoise: " << e.what() << '\n';
    return 128 + e.signal;
  } catch (const std::exception& e) {
    std::cerr << "poise: error: " << e.what() << '\n';
    return 1;
  }
  if ((*run || *sens) && study.empty()) {
    if (opt.resume.empty()) {
      std::cerr << "poise: STUDY is required (the study file), or --resume DIR to continue a run\n";
      return 2;
    }
    try {
      study = poise::engine::study_file_of_run(opt.resume);
    } catch (const std::exception& e) {
      std::cerr << "poise: " << e.what() << "\nNothing was run.\n";
      return 2;
    }
  }
  for (const auto& setting : settings) {
    const auto eq = setting.find('=');
    if (eq == std::string::npos || eq == 0) {
      std::cerr << "poise run: --set '" << setting << "': expected KEY=VALUE, e.g. --set \"yaw.bearing_span=70 mm\"\n";
      return 2;
    }
    opt.overrides[setting.substr(0, eq)] = setting.substr(eq + 1);
  }
  if (samples > 0) opt.samples = samples;
  if (max_samples > 0) opt.max_samples = max_samples;
  if (*sens) {
    if (base == 0 && opt.resume.empty()) {
      std::cerr << "poise sensitivity: --base N is required (base rows of the Saltelli layout)\n";
      return 2;
    }
    opt.sensitivity_base = base;
    if (sens->count("--seed")) opt.seed = seed;
  }
  if (!run->count("--seed") && !replay->count("--seed")) {
  } else {
    opt.seed = seed;
  }
  opt.progress = !quiet;
  opt.plots = !no_plots;
  const bool root = poise::sampling::Cluster::root();

  try {
    if (*validate) {
      std::cout << poise::engine::validate_study(study) << '\n';
    } else if (*run || *sens) {
      const std::string dir = poise::engine::run_study(study, opt);
      if (root) {
        // The answer is the last line before the report's path: the sentence summary.json
        // and the report open with.
        const poise::engine::RunAnswer answer = poise::engine::run_answer(dir);
        if (!answer.answer.empty()) std::cout << answer.answer << '\n';
        std::cout << "report: " << dir << "/report.html\n";
        if (opt.require && answer.met != true) return 3;
      }
    } else if (*replay) {
      std::cout << poise::engine::replay_sample(study, index, opt).dump(2) << '\n';
    }
  } catch (const poise::engine::ValidationError& e) {
    if (root) std::cerr << "poise: " << e.what() << "\nNothing was run.\n";
    return 2;
  } catch (const poise::UsageError& e) {
    if (root) std::cerr << "poise: " << e.what() << "\nNothing was run.\n";
    return 2;
  } catch (const poise::engine::Interrupted& e) {
    if (root) std::cerr << "\npoise: " << e.what() << '\n';
    return 128 + e.signal;
  } catch (const std::exception& e) {
    std::cerr << "poise: error: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
