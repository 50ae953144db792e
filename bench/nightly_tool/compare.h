#pragma once
/// What the sections of the compare mode share (compare.cc runs them): the options, the tally of
/// the figures compared, one figure judged against another, and the timing rules of the benchmark
/// and derived-figure sections.
#include <string>
#include <vector>

#include "nightly_common.h"

namespace poise::nightly {

struct Options {
  double k = 3.0;
  double floor = 0.05;
  double wall_warn = 0.25;
  // A baseline ratio regresses below previous (reference) / (1 + ratio_band): 0.2 catches a 1.3x
  // slowdown of Poise (ratio / 1.3 < ratio / 1.2) and leaves 20 % to the ratio's own scatter.
  double ratio_band = 0.2;
  bool all = false;
  bool warn_timing = false;  // timing regressions only warn (bench/nightly --quick: 2 repetitions)
  double gross = 0.5;        // ... unless worse by more than max(2 x band, gross)
  double idle_margin = 0.5;  // multi-threaded figures judged below load (cores - 1) + idle_margin
  double memory_band = 0.25;  // a LOS run at scale regresses when its peak memory grows beyond x1.25
};

struct Tally {
  int compared = 0, warnings = 0, not_judged = 0;
  std::vector<std::string> regressions;
};

// worse = how much worse the current figure is than the other (> 0 worse), in relative terms
// of the figure's own sense: lower-better: cur/other - 1; higher-better: other/cur - 1.
double worse_by(double cur, double other, bool lower_better);

struct Verdict {
  std::string text;
  bool regression = false;
};

// "REGRESSION" when worse by more than band, "better" when better by more than band, else "ok".
Verdict judge(double cur, double other, bool lower_better, double band);

// A run file as the report names it: path (date, commit, machine, repetitions[, quick]).
std::string describe(const json& run, const std::string& path);

// The machine a run (or a reference's source run) was recorded on, as "hostname | cpu model |
// N cores"; empty when the file does not say. Absolute times are judged only between runs of the
// same machine: the calibration workload does not absorb every benchmark family's difference
// between machines (measured: an unchanged binary's balancing benchmarks read 1.12-1.14x against
// a reference from another machine of the same kind).
std::string machine_key(const json& run);

// The rules of timing figures (benchmarks, derived figures; compare_figures.cc) on this machine.
struct TimingRules {
  const Options& opt;
  Tally& t;
  int cores;  // the current run's machine's (0: not recorded)
  // Absolute times (the benchmarks' calibrated figures, the studies' wall times) are judged
  // against the previous run and the reference only when those were recorded on this machine
  // (machine_key); ratios, memory and statistics are judged whatever the machine.
  bool times_vs_previous = true;
  bool times_vs_reference = true;
  // A timing figure beyond its band: a regression, or with --warn-timing (a quick run's 2
  // repetitions cannot measure the noise) a warning, unless it is worse by more than twice its
  // band and by at least 50 %: a slowdown that large shows even in 2 repetitions.
  bool gross(double worse, double band) const;
  void flag_timing(const std::string& what, double worse, double band) const;
  std::string warn_suffix(const Verdict& v, double worse, double band) const;
  // Multi-threaded figures (real time, 2-thread speed-ups) need the cores free: judged only when
  // the load average beside them is below (cores - 1) + idle_margin; otherwise a note.
  std::string too_loaded(const json& e) const;
  // band = max(floor, k * sqrt(n1^2 + n2^2)).
  double band_of(double n1, double n2) const;
};

// The sections of the report, in their order (targets: the reference's or default_targets()).
// Benchmarks: the calibrated figures against the previous run and the reference (compare_figures.cc).
void compare_benchmarks(const json& cur, const json& prev, const json& ref, const TimingRules& rules);
// Derived figures: speed-ups compared (ratios already), absolute figures against targets (compare_figures.cc).
void compare_derived(const json& cur, const json& prev, const json& ref, const json& targets,
                     const TimingRules& rules);
// Baseline ratios (bench/baselines/compare.py): NumPy/SciPy CPU time over Poise's, measured in
// the same run, so a loaded machine slows both sides. Below the target: a warning; below the
// previous run's or the reference's ratio / (1 + ratio_band): a regression (a warning with
// --warn-timing). Baselines not run, a ratio not computed, or no reference ratio: never a failure.
// (compare_baselines.cc)
void compare_baselines(const json& cur, const json& prev, const json& ref, const Options& opt, Tally& t);
// A LOS run at scale (bench/los_scale): peak memory against its target (a warning) and the
// previous run's at the same sample count (a regression beyond x(1 + memory_band)); the
// whole-study speed-up against its target (a warning, judged below the load rule); under MPI
// the same data at every rank count (else a regression) and rank 0's growth (a warning).
// (compare_scale.cc)
void compare_scale(const json& cur, const json& prev, const TimingRules& rules);
// Reference studies: statistics against the reference, wall times against the previous run (compare_studies.cc).
void compare_studies(const json& cur, const json& prev, const json& ref, const TimingRules& rules);

}  // namespace poise::nightly
