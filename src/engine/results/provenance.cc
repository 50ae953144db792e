#include "engine/results/provenance.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <oneapi/tbb/version.h>
#include <toml++/toml.h>
#include <Eigen/Core>
#include <boost/uuid/detail/sha1.hpp>
#include <boost/version.hpp>
#include <cerrno>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "core/error.h"
#include "core/format.h"
#include "core/version.h"

namespace poise::engine {
namespace fs = std::filesystem;

std::string file_sha1(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  boost::uuids::detail::sha1 h;
  h.process_bytes(bytes.data(), bytes.size());
  boost::uuids::detail::sha1::digest_type d;
  h.get_digest(d);
  std::string hex;
  for (const auto word : d) hex += fmt::format("{:08x}", word);  // five 32-bit words
  return hex;
}

namespace {
// Standard output of a program run directly, without a shell (posix_spawnp, the arguments as
// given, standard error to /dev/null), trailing blanks removed; "" if it cannot be started or
// fails.
std::string program_output(const std::vector<std::string>& args) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) return "";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(fds[1]);
  std::string out;
  if (rc == 0) {
    char buf[256];
    for (;;) {
      const ssize_t n = read(fds[0], buf, sizeof buf);
      if (n > 0) {
        out.append(buf, static_cast<std::size_t>(n));
      } else if (n == 0 || errno != EINTR) {
        break;
      }
    }
  }
  close(fds[0]);
  if (rc != 0) return "";
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return "";
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  return out;
}
}  // namespace

std::string git_commit() {
  const std::string dir = kSourceDir;
  std::string c = program_output({"git", "-C", dir, "rev-parse", "HEAD"});
  if (c.empty()) return kGitCommit;
  if (!program_output({"git", "-C", dir, "status", "--porcelain", "--untracked-files=no"}).empty()) {
    c += "-dirty";
  }
  return c;
}

nlohmann::json library_versions(bool plots) {
  nlohmann::json j;
  j["poise"] = kVersion;
  j["compiler"] = std::string("g++ ") + __VERSION__;
  j["eigen"] = std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
               std::to_string(EIGEN_MINOR_VERSION);
  j["onetbb"] = TBB_VERSION_STRING;
  j["boost"] = std::to_string(BOOST_VERSION / 100000) + "." + std::to_string(BOOST_VERSION / 100 % 1000) + "." +
               std::to_string(BOOST_VERSION % 100);
  j["tomlplusplus"] =
      std::to_string(TOML_LIB_MAJOR) + "." + std::to_string(TOML_LIB_MINOR) + "." + std::to_string(TOML_LIB_PATCH);
  j["nlohmann_json"] = std::to_string(NLOHMANN_JSON_VERSION_MAJOR) + "." + std::to_string(NLOHMANN_JSON_VERSION_MINOR) +
                       "." + std::to_string(NLOHMANN_JSON_VERSION_PATCH);
  j["random123"] = "Philox4x64-10 (Random123, Debian librandom123-dev)";
  if (plots) {
    const std::string gp = program_output({"gnuplot", "--version"});
    j["gnuplot"] = gp.empty() ? "not found" : gp;
  } else {
    j["gnuplot"] = "not run (no plots)";
  }
  return j;
}

std::string now_iso8601() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S%z", &tm);
  return buf;
}

std::string make_run_folder(const std::string& results_root, const std::string& study_name, const std::string& out) {
  std::error_code ec;
  if (!out.empty()) {
    if (fs::exists(fs::path(out) / "samples.csv")) {
      throw UsageError("--out " + out + " already holds a run (samples.csv); choose a new folder");
    }
    fs::create_directories(out, ec);
    if (ec) throw Error("cannot create output folder " + out + ": " + ec.message());
    return out;
  }
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
  const fs::path base = fs::path(results_root) / study_name;
  fs::create_directories(base, ec);
  if (ec) throw Error("cannot create results folder " + base.string() + ": " + ec.message());
  for (int k = 1; k < 10000; ++k) {
    const fs::path p = base / (k == 1 ? std::string(stamp) : std::string(stamp) + "-" + std::to_string(k));
    if (fs::create_directory(p, ec)) return p.string();  // atomic: fails if it exists
  }
  throw Error("cannot find a free run folder under " + base.string());
}

}  // namespace poise::engine
