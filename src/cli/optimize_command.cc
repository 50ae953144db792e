#include "cli/optimize_command.h"

#include "engine/kind_interface/programs_allowed.h"

#include <cstdint>
#include <iostream>
#include <memory>
#include <optional>

#include "core/error.h"
#include "engine/study_files/toml_reader.h"
#include "optimize/optimization_study.h"

namespace poise::cli {
namespace {

const char* kOptimizeHelp = R"(
An optimization file names a base study (any study file), design variables (model keys with
bounds in their unit), an objective (a statistic of one of the study's outputs, or the sum of
design variables such as bearing spans), constraints, and the NLopt algorithm. Every
evaluation runs the base study with the same seed and sample count (common random numbers),
so the objective is smooth in the design. An evaluation in which more than the base study's
[sampling] max_failure_share of the samples failed counts as failed (history.csv keeps the
failure share of every evaluation).

Constraints: [[constraint]] output, statistic, at_most = x | at_least = x, and optionally
bound = "upper95" (at_most) or "lower95" (at_least): a chance constraint with confidence,
met when the one-sided 95% bound of the statistic meets the limit, not just its point value
(p<q>: order-statistic bound; mean: Student t; fraction_le/ge:<x>, the share of units meeting
a requirement: Clopper-Pearson; with [optimization] replicate_size, or the base study's, the
spread of randomized lhs / sobol replicates). An optimum of a point-value constraint sits on
its limit, so about half of its fresh checks land beyond it: state the bound to release.

The answer must hold on samples the search never saw:
  * Discrete choices ([[choice]] parameter, values) are enumerated, each with its own search;
    a selection set of fresh samples picks the headline (best on fresh samples among those
    meeting their constraints) and each value's best combination, a second fresh set (the
    [verification] samples and seed) compares them: paired differences with 95% intervals,
    constraints re-checked, and equivalence within [verification] equivalence_margin
    ("5%" of the better figure, or a number in the objective's unit): shown only if the
    whole interval of the difference lies within the margin.
  * The headline design's fresh-sample check decides: each constraint passes (its 95%
    interval, or its stated bound, meets the limit), straddles the limit, or fails. If it
    does not pass, the run says so (terminal, summary.json "verified", the report's top),
    searches for the nearest design that passes (each failing limit tightened by its excess,
    up to [verification] max_nearest_rounds rounds, re-checked on other fresh samples) and
    exits with status 3.
  * [optimization] replicates = R repeats the headline's search with R - 1 other seeds: the
    spread of each variable and of the objective; the answer is rounded to what it supports.
  * [optimization] search_model = "fast" runs the searches (and a choice study's selection set
    and Pareto front) on the kind's fast model (balancing machine: the exact steady state;
    gimbal: each position's mean current over whole periods); the comparison set and the
    check run the full model and decide. The answer says how far the two are apart on the
    headline's fresh samples and what each model ran (summary.json "fast_model", "cost").
Besides model keys, a gimbal study takes study keys: group.positions, group.placement
(sequential, interleaved, back_and_forth), group.repeats. [overrides] sets keys for every
evaluation. A second objective ([pareto] output, statistic, points) traces the Pareto front by
the epsilon-constraint method; each front point is run on fresh samples.

Algorithms: cobyla (local, derivative-free, native inequality constraints: the default),
bobyqa (local, smooth objectives; constraints through an augmented Lagrangian), sbplx and
neldermead (local, tolerant of non-smooth objectives), direct_l (global, deterministic, few
variables), isres (global, stochastic, native constraints, many evaluations).

Statistics: mean, std, min, max, p<q> (p50, p95, p99.73), fraction_le:<x>, fraction_ge:<x>.

Prints the answer in one sentence on stdout; progress and ETA (searches and fresh-sample
checks) on stderr. Writes results/<name>/<run id>/: history.csv (every evaluation: choices and
constraints by name, failure share), summary.json ("answer", "verified", verification,
nearest_passing_design, optimum_spread, choices_compared, pareto), pareto.csv,
plots/convergence.svg and pareto.svg, report.html (opening with the answer).

Exit status:
  0  the optimum passed its fresh-sample check (verified)
  1  the run failed: no design met the constraints (the folder still holds the history)
  2  invalid input (nothing was run)
  3  design not verified: the optimum failed its fresh-sample check or its interval
     straddles a limit (the answer names the nearest design that passes, or says none found)

Examples:
  poise optimize studies/bearing_span_sizing.toml
  poise optimize studies/spring_plate_sizing.toml --threads 2 --seed 7 --out /tmp/plates)";

}  // namespace

OptimizeHandler add_optimize_command(CLI::App& app) {
  struct Options {
    std::string file;
    engine::RunOptions run;
    bool quiet = false, no_plots = false;
    std::optional<std::uint64_t> seed;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub =
      app.add_subcommand("optimize", "optimize design variables or a test plan over a Monte Carlo study (NLopt)");
  sub->add_option("FILE", opt->file, "optimization file (TOML), e.g. studies/bearing_span_sizing.toml")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option("--out,-o", opt->run.out, "result folder (default results/<name>/<run id>)");
  sub->add_option("--results-root", opt->run.results_root, "where default result folders go (default: results)");
  sub->add_option("--threads,-j", opt->run.threads, "worker threads per evaluation (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--seed", opt->seed, "seed of the search's samples (default: the file's [optimization] seed)");
  sub->add_flag_callback(
      "--allow-programs", [] { engine::allow_programs(true); },
      "start the program a model file names (kind = \"external\"): only for a program you trust");
  sub->add_flag("--quiet,-q", opt->quiet, "no progress on stderr");
  sub->add_flag("--no-plots", opt->no_plots, "skip gnuplot figures");
  sub->footer(kOptimizeHelp);
  return [sub, opt]() -> std::optional<int> {
    if (!*sub) return std::nullopt;
    opt->run.progress = !opt->quiet;
    opt->run.plots = !opt->no_plots;
    try {
      const optimize::OptimizationRun r = optimize::run_optimization(opt->file, opt->run, opt->seed);
      if (r.exit_status == optimize::kExitNotVerified) {
        std::cout << "DESIGN NOT VERIFIED on fresh samples (exit status 3).\n";
      }
      std::cout << "answer: " << r.answer << "\nreport: " << r.dir << "/report.html\n";
      return r.exit_status;
    } catch (const engine::ValidationError& e) {
      std::cerr << "poise: " << e.what() << "\nNothing was run.\n";
      return optimize::kExitInvalidInput;
    } catch (const UsageError& e) {  // e.g. --out into a folder that holds a run
      std::cerr << "poise: " << e.what() << "\nNothing was run.\n";
      return optimize::kExitInvalidInput;
    } catch (const std::exception& e) {
      std::cerr << "poise: error: " << e.what() << '\n';
      return optimize::kExitRunFailed;
    }
  };
}

}  // namespace poise::cli
