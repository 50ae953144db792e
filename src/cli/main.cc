// poise: command-line entry point. See `poise --help`.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "cli/balance_command.h"
#include "cli/budget_command.h"
#include "cli/count_check.h"
#include "cli/diagnose_command.h"
#include "cli/error_mechanisms_command.h"
#include "cli/fit_command.h"
#include "cli/keys_command.h"
#include "cli/mass_properties_command.h"
#include "cli/optimize_command.h"
#include "cli/record_command.h"
#include "cli/study_commands.h"
#include "core/error.h"
#include "core/version.h"
#include "engine/results/fault_injection.h"
#include "engine/run/study_runner.h"
#include "engine/study_files/toml_reader.h"
#include "kinds/registry.h"
#include "sampling/distributed.h"

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
  // Test hooks of the failure-handling tests (POISE_INJECT_*), read here only: the engine
  // takes them injected (engine/results/fault_injection.h).
  poise::engine::fault_injection::set_from_environment();
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

  poise::cli::StudyCommands study_commands(app);  // run, sensitivity, validate, replay
  const poise::cli::FitHandler fit = poise::cli::add_fit_command(app);
  const poise::cli::BalanceHandler balance = poise::cli::add_balance_command(app);
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
  if (poise::sampling::Cluster::size() > 1 && !study_commands.distributes()) {
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
    if (const auto status = balance()) return *status;
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
  return study_commands().value_or(0);
}
