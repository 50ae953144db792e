#include "cli/optimize_command.h"

#include <iostream>
#include <memory>

#include "optimize/optimization_study.h"
#include "engine/toml_reader.h"

namespace poise::cli {
namespace {

const char* kOptimizeHelp = R"(
An optimization file names a base study (any study file), design variables (model keys with
bounds in their unit), an objective (a statistic of one of the study's outputs, or the sum of
design variables such as bearing spans), constraints (statistics with at_least / at_most), and
the NLopt algorithm. Every evaluation runs the base study with the same seed and sample count
(common random numbers), so the objective is smooth in the design; the optimum is then run
again with fresh random numbers and more samples ([verification]) and reported with CIs.
Discrete choices ([[choice]] parameter, values) are enumerated, each with its own search;
the best design of each is then verified on the same fresh samples and compared with the best
(paired bootstrap interval of the difference), also per value of each choice parameter ("18 or
36 positions?"). Besides model keys, a gimbal study takes study keys: group.positions,
group.placement (sequential, interleaved, back_and_forth), group.repeats. [overrides] sets
keys for every evaluation. A second objective ([pareto] output, statistic, points) traces the
Pareto front by the epsilon-constraint method; each front point is verified with CIs.

Algorithms: cobyla (local, derivative-free, native inequality constraints: the default),
bobyqa (local, smooth objectives; constraints through an augmented Lagrangian), sbplx and
neldermead (local, tolerant of non-smooth objectives), direct_l (global, deterministic, few
variables), isres (global, stochastic, native constraints, many evaluations).

Statistics: mean, std, min, max, p<q> (p50, p95, p99.73), fraction_le:<x>, fraction_ge:<x>.

Writes results/<name>/<run id>/: history.csv (every evaluation), summary.json (runs, optimum,
verification, choices_compared, pareto), pareto.csv, plots/convergence.svg and pareto.svg,
report.html. Exit status 0 with a feasible optimum;
1 if no design met the constraints (the folder still holds the history); 2 invalid input.

Examples:
  poise optimize studies/bearing_span_sizing.toml
  poise optimize studies/spring_plate_sizing.toml --threads 2 --out /tmp/plates)";

}  // namespace

OptimizeHandler add_optimize_command(CLI::App& app) {
  struct Options {
    std::string file;
    studies::RunOptions run;
    bool quiet = false, no_plots = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand("optimize", "optimize design variables or a test plan over a Monte Carlo study (NLopt)");
  sub->add_option("FILE", opt->file, "optimization file (TOML), e.g. studies/bearing_span_sizing.toml")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option("--out,-o", opt->run.out, "result folder (default results/<name>/<run id>)");
  sub->add_option("--results-root", opt->run.results_root, "where default result folders go (default: results)");
  sub->add_option("--threads,-j", opt->run.threads, "worker threads per evaluation (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  sub->add_flag("--quiet,-q", opt->quiet, "no progress on stderr");
  sub->add_flag("--no-plots", opt->no_plots, "skip gnuplot figures");
  sub->footer(kOptimizeHelp);
  return [sub, opt]() -> std::optional<int> {
    if (!*sub) return std::nullopt;
    opt->run.progress = !opt->quiet;
    opt->run.plots = !opt->no_plots;
    try {
      const std::string dir = optimize::run_optimization(opt->file, opt->run);
      std::cout << "report: " << dir << "/report.html\n";
      return 0;
    } catch (const studies::ValidationError& e) {
      std::cerr << "poise: " << e.what() << "\nNothing was run.\n";
      return 2;
    } catch (const std::exception& e) {
      std::cerr << "poise: error: " << e.what() << '\n';
      return 1;
    }
  };
}

}  // namespace poise::cli
