#pragma once
/// The modes of poise_nightly_compare (main.cc dispatches): each takes the arguments after the
/// mode's name (compare: all of them), returns the exit status and throws InputError on bad input.
#include <string>
#include <vector>

namespace poise::nightly {

// Compare a nightly run with the previous run and the reference (compare.cc).
int run_compare(const std::vector<std::string>& args);
// Time the calibration workload (calibrate.cc).
int run_calibrate(const std::vector<std::string>& args);
// Assemble one nightly run file from the raw outputs (collect.cc).
int run_collect(const std::vector<std::string>& args);
// Write the reference figures from a run (make_reference.cc).
int run_make_reference(const std::vector<std::string>& args);
// machine-key RUN.json: prints the machine the run was recorded on (compare.h machine_key), so
// that bench/nightly picks the previous run of the same machine.
int run_machine_key(const std::vector<std::string>& args);

}  // namespace poise::nightly
