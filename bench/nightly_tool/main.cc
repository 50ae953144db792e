/// poise_nightly_compare: the JSON side of bench/nightly (issue 9 item 7). Five modes:
///
///   poise_nightly_compare CURRENT.json [--previous PREV.json] [--reference REF.json]
///                         [--k K] [--floor F] [--all]
///       compare a nightly run with the previous run and with the stored reference figures;
///       prints a table; exit 0 fine, 3 regression, 2 bad input.
///   poise_nightly_compare calibrate [--repetitions N] [--min-time S]
///       time the fixed calibration workload; prints {"values": [ns per step, ...]}.
///   poise_nightly_compare collect --out FILE --meta META.json [--calibration CAL.json]...
///                         [--bench BINARY RC BENCH.json]... [--study NAME RC WALL_S SUMMARY.json]...
///                         [--study-reference NAME FILE VERDICT]...
///                         [--baselines BASELINES.json] [--scale SCALE.json] [--load NAME BEFORE AFTER]...
///       assemble one nightly file from the raw outputs (Google Benchmark JSON, summary.json,
///       bench/baselines/compare.py --json).
///   poise_nightly_compare make-reference CURRENT.json --out REF.json [--old OLD_REF.json]
///       write the reference figures from a run (targets kept from OLD_REF.json if given).
///   poise_nightly_compare machine-key RUN.json
///       print the machine a run or reference was recorded on (bench/nightly's previous run).
///
/// The rule (also in bench/NIGHTLY.md): a timing figure is a benchmark's median time per iteration
/// (CPU time; real time for the multi-threaded /real_time runs) divided by the calibration
/// workload's median CPU time in the calibration runs just before and after its program (same
/// machine, same time: a slower or faster machine cancels out). The noise of a median over n
/// repetitions is its relative standard error, 1.2533 sd / sqrt(n) / median, widened by
/// t(0.975, n - 1) / 1.96 since sd is estimated from n values (x1.42 for n = 5); a calibrated
/// figure's noise combines the benchmark's and the calibration's, sqrt(noise_bench^2 +
/// noise_calibration^2). A figure regresses when it is worse than the previous run's (or the
/// reference's) by more than
/// band = max(floor, k * sqrt(noise_current^2 + noise_other^2)), k = 3, floor = 5 %.
/// The 2-thread speed-ups are ratios already (no calibration) and follow the same rule. Multi-
/// threaded figures (real-time benchmarks, speed-ups) are judged only when the load average beside
/// them (bench/nightly records it before and after each binary) is below (cores - 1) + 0.5: on a
/// loaded machine they measure the neighbours. With --warn-timing (quick runs) a timing regression
/// only warns unless worse by more than max(2 x band, 50 %).
/// Reference studies (fixed seed and sample count, deterministic): bench/nightly compares each one's
/// samples with its one recorded reference (tests/data/study_reference/, as study_reference_test
/// does) and a difference is a regression. Absolute targets (README) are checked and only warned about.
/// Study wall times (one run each, no noise estimate) are warned about beyond 25 %.
/// Absolute times (benchmarks, study wall times) are judged only against runs of the same machine
/// (host, CPU model, cores: machine_key); against another machine's previous run or reference they
/// are shown, not judged, and a machine's first run is its baseline.
/// Baseline ratios (NumPy/SciPy CPU time over Poise's, same run): a warning below their target, a
/// regression below the previous run's or the reference's ratio / (1 + ratio_band), ratio_band 0.2.
///
/// This file: the help text and main(), which hands the arguments to a mode (nightly_modes.h).
/// The modes: compare.cc (with compare.h, compare_figures.cc, compare_baselines.cc,
/// compare_studies.cc), calibrate.cc, collect.cc, make_reference.cc; what they share:
/// nightly_common.h.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "nightly_common.h"
#include "nightly_modes.h"

namespace poise::nightly {
namespace {

void print_help() {
  std::printf(
      "poise_nightly_compare: compare a nightly run (bench/nightly) with the previous run and the reference\n"
      "\n"
      "  poise_nightly_compare CURRENT.json [--previous PREV.json] [--reference REF.json] [options]\n"
      "      --k K           noise multiplier of the band (default 3)\n"
      "      --floor F       smallest band, relative (default 0.05 = 5%%)\n"
      "      --wall-warn W   warn when a study's wall time grows by more than W (default 0.25)\n"
      "      --all           print every figure, not only the changed ones\n"
      "      --warn-timing   timing regressions only warn (bench/nightly --quick), unless worse by more than\n"
      "                      max(2 x band, G)\n"
      "      --gross G       (default 0.5: 1.5x slower)\n"
      "      --idle-margin M multi-threaded figures (real time, speed-ups) are judged only when the load\n"
      "                      average beside them is below (cores - 1) + M (default 0.5)\n"
      "      --memory-band B a LOS run at scale (bench/los_scale) regresses when its peak memory grows beyond\n"
      "                      the previous run's x(1+B) at the same sample count (default 0.25)\n"
      "      --ratio-band B  a baseline ratio regresses below previous/reference / (1+B) (default 0.2)\n"
      "  Rule: a benchmark figure is its median time per iteration (CPU time; real time for /real_time\n"
      "  runs) / the calibration median of the same run; it regresses when worse than previous/reference\n"
      "  by more than max(floor, k*sqrt(n1^2+n2^2)), n = the figures' noise (relative standard error of\n"
      "  the medians x t(0.975, n-1)/1.96, benchmark and calibration combined). Speed-ups (2 threads over 1)\n"
      "  likewise, judged only below a load of (cores - 1) + M. Study samples (fixed seeds) must equal their\n"
      "  recorded reference (tests/data/study_reference/, bench/nightly's verdict). Targets: warnings only.\n"
      "  Baseline ratios (NumPy/SciPy CPU time / Poise's, one run): below previous/reference / (1+B) a\n"
      "  regression (1.3x slower Poise is caught at B 0.2); below target, not run or no reference: warnings.\n"
      "  Exit status: 0 fine (warnings allowed), 3 regression (listed at the end), 2 bad input or usage.\n"
      "\n"
      "  poise_nightly_compare calibrate [--repetitions N] [--min-time S]     time the calibration workload\n"
      "  poise_nightly_compare collect --out FILE --meta META.json [--calibration CAL.json]...\n"
      "        [--bench BINARY EXIT_STATUS BENCH.json]... [--study NAME EXIT_STATUS WALL_S SUMMARY.json]...\n"
      "        [--study-reference NAME FILE VERDICT]...  (same | differs: ... | missing: ..., against the recorded one)\n"
      "        [--baselines BASELINES.json]    (bench/baselines/compare.py --json, or {\"status\": \"not run\"})\n"
      "        [--scale SCALE.json]            (bench/los_scale --json, or {\"status\": \"not run\"})\n"
      "        [--load NAME BEFORE AFTER]...   (1-minute load average around a binary; NAME study:S for a study)\n"
      "  poise_nightly_compare make-reference CURRENT.json --out REF.json [--old OLD_REF.json]\n"
      "  poise_nightly_compare machine-key RUN.json    (the machine a run was recorded on: host | CPU | cores)\n"
      "\n"
      "See bench/NIGHTLY.md.\n");
}

}  // namespace
}  // namespace poise::nightly

int main(int argc, char** argv) {
  using namespace poise::nightly;
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (args.empty()) {
      print_help();
      return kExitInput;
    }
    if (args[0] == "--help" || args[0] == "-h") {
      print_help();
      return kExitOk;
    }
    const std::string mode = args[0];
    const std::vector<std::string> rest(args.begin() + 1, args.end());
    if (mode == "calibrate") return run_calibrate(rest);
    if (mode == "collect") return run_collect(rest);
    if (mode == "make-reference") return run_make_reference(rest);
    if (mode == "machine-key") return run_machine_key(rest);
    return run_compare(args);
  } catch (const InputError& e) {
    std::fprintf(stderr, "poise_nightly_compare: %s\n", e.what());
    return kExitInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "poise_nightly_compare: %s\n", e.what());
    return kExitInput;
  }
}
