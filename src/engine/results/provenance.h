#pragma once
/// Provenance of a run: what produced a result folder, so it can be reproduced.
#include <nlohmann/json.hpp>
#include <string>

namespace poise::engine {

/// SHA-1 of a file's bytes, hex (Boost.UUID's SHA-1); "" if unreadable.
std::string file_sha1(const std::string& path);
/// Commit of the source tree Poise was built from (git at run time, else configure time),
/// with "-dirty" when the tree has uncommitted changes. git runs without a shell.
std::string git_commit();
/// Versions of Poise, the compiler and the libraries linked in; gnuplot's (a program run once,
/// `gnuplot --version`) only when the run draws plots.
nlohmann::json library_versions(bool plots);
/// Creates a fresh run folder: `out` if given (refused if it holds a samples.csv), else
/// results/<study>/<YYYYmmdd-HHMMSS>[-k] under `results_root`. Never overwrites a run.
std::string make_run_folder(const std::string& results_root, const std::string& study_name, const std::string& out);
/// Local time as ISO 8601.
std::string now_iso8601();

}  // namespace poise::engine
