#pragma once
// Helpers shared by the tests of every layer: temporary files, reading the repository's files,
// running the built poise. Layer-free (no Poise header); study run options: study_run_options.h.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace poise::test {

/// The build folder of the running test program: the nearest folder above it that holds
/// CMakeCache.txt. Found when the test runs, not compiled in, so that a test's object file is
/// the same in every checkout and build folder (ccache shares it between clean clones).
inline const std::filesystem::path& build_dir() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path p = std::filesystem::read_symlink("/proc/self/exe").parent_path();
    while (!std::filesystem::exists(p / "CMakeCache.txt")) {
      if (p == p.root_path()) throw std::runtime_error("test setup: no CMakeCache.txt above the test program");
      p = p.parent_path();
    }
    return p;
  }();
  return dir;
}

/// The source folder this build was configured from (CMAKE_HOME_DIRECTORY of CMakeCache.txt).
inline const std::string& source_dir() {
  static const std::string dir = [] {
    std::ifstream cache(build_dir() / "CMakeCache.txt");
    const std::string key = "CMAKE_HOME_DIRECTORY:INTERNAL=";
    for (std::string line; std::getline(cache, line);) {
      if (line.rfind(key, 0) == 0) return line.substr(key.size());
    }
    throw std::runtime_error("test setup: CMakeCache.txt names no CMAKE_HOME_DIRECTORY");
  }();
  return dir;
}

/// The built `poise` executable, and the other programs the build puts beside it.
inline std::string built_program(const std::string& name) { return (build_dir() / name).string(); }
inline std::string poise_binary() { return built_program("poise"); }

inline std::string source_path(const std::string& rel) { return (std::filesystem::path(source_dir()) / rel).string(); }

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline void write_text(const std::string& path, const std::string& text) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path) << text;
}

/// A fresh temporary folder per test, removed at the end.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("poise_test_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
             std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// Replaces the first occurrence of `from` (which must exist) in text.
inline std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "test setup: '" << from << "' not found";
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

/// Exit status and captured output of a run of the built `poise` executable.
struct RunResult {
  int status = -1;
  std::string out, err;
};

/// Runs `poise <args>` with stdout and stderr captured through files in `dir`.
inline RunResult run_poise(const TempDir& dir, const std::string& args) {
  const std::string out = dir.file("stdout.txt"), err = dir.file("stderr.txt");
  // Appended piece by piece: g++ 12 -O3 warns (-Wstringop-overflow, a false positive) on
  // "'" + std::string&& here.
  std::string cmd = "'";
  cmd += poise_binary();
  cmd += "' " + args + " >'" + out + "' 2>'" + err + "'";
  const int raw = std::system(cmd.c_str());
  RunResult r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  return r;
}

}  // namespace poise::test
