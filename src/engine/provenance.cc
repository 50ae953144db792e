#include "engine/provenance.h"

#include <Eigen/Core>
#include <boost/uuid/detail/sha1.hpp>
#include <boost/version.hpp>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <oneapi/tbb/version.h>
#include <toml++/toml.h>

#include "core/error.h"
#include "core/version.h"

namespace poise::studies {
namespace fs = std::filesystem;

std::string file_sha1(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  boost::uuids::detail::sha1 h;
  h.process_bytes(bytes.data(), bytes.size());
  boost::uuids::detail::sha1::digest_type d;
  h.get_digest(d);
  char buf[41];
  for (int i = 0; i < 5; ++i) std::snprintf(buf + 8 * i, 9, "%08x", d[i]);
  return buf;
}

namespace {
std::string run_capture(const std::string& cmd) {
  std::string out;
  if (FILE* p = popen(cmd.c_str(), "r")) {
    char buf[256];
    while (fgets(buf, sizeof buf, p)) out += buf;
    pclose(p);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  return out;
}
}  // namespace

std::string git_commit() {
  const std::string dir = kSourceDir;
  std::string c = run_capture("git -C '" + dir + "' rev-parse HEAD 2>/dev/null");
  if (c.empty()) return kGitCommit;
  if (!run_capture("git -C '" + dir + "' status --porcelain --untracked-files=no 2>/dev/null").empty()) {
    c += "-dirty";
  }
  return c;
}

nlohmann::json library_versions() {
  nlohmann::json j;
  j["poise"] = kVersion;
  j["compiler"] = std::string("g++ ") + __VERSION__;
  j["eigen"] = std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) +
               "." + std::to_string(EIGEN_MINOR_VERSION);
  j["onetbb"] = TBB_VERSION_STRING;
  j["boost"] = std::to_string(BOOST_VERSION / 100000) + "." + std::to_string(BOOST_VERSION / 100 % 1000) +
               "." + std::to_string(BOOST_VERSION % 100);
  j["tomlplusplus"] = std::to_string(TOML_LIB_MAJOR) + "." + std::to_string(TOML_LIB_MINOR) + "." +
                      std::to_string(TOML_LIB_PATCH);
  j["nlohmann_json"] = std::to_string(NLOHMANN_JSON_VERSION_MAJOR) + "." +
                       std::to_string(NLOHMANN_JSON_VERSION_MINOR) + "." +
                       std::to_string(NLOHMANN_JSON_VERSION_PATCH);
  j["random123"] = "Philox4x64-10 (Random123, Debian librandom123-dev)";
  const std::string gp = run_capture("gnuplot --version 2>/dev/null");
  j["gnuplot"] = gp.empty() ? "not found" : gp;
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

std::string make_run_folder(const std::string& results_root, const std::string& study_name,
                            const std::string& out) {
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

}  // namespace poise::studies
