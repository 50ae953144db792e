#include "engine/checked_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <utility>

namespace poise::studies {
namespace {

// Bytes the test hook still lets through (max = no hook).
std::atomic<std::size_t>& injected_budget() {
  static std::atomic<std::size_t> budget = [] {
    const char* env = std::getenv("POISE_INJECT_WRITE_FAILURE_AFTER");
    return env ? static_cast<std::size_t>(std::strtoull(env, nullptr, 10)) : std::numeric_limits<std::size_t>::max();
  }();
  return budget;
}

// How many of `n` bytes to `path` the hook lets through; the rest fail with ENOSPC.
std::size_t allowed_by_hook(const std::string& path, std::size_t n) {
  static const char* only = std::getenv("POISE_INJECT_WRITE_FAILURE_FILE");
  if (only && *only && std::filesystem::path(path).filename() != only) return n;
  auto& budget = injected_budget();
  std::size_t left = budget.load();
  if (left == std::numeric_limits<std::size_t>::max()) return n;
  std::size_t take = 0;
  do {
    take = std::min(left, n);
  } while (!budget.compare_exchange_weak(left, left - take));
  return take;
}

}  // namespace

WriteError::WriteError(std::string path, const std::string& reason)
    : Error(path + ": " + reason), path_(std::move(path)) {}

CheckedFile::CheckedFile(std::string path, bool append) : path_(std::move(path)) {
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | (append ? O_APPEND : O_TRUNC), 0644);
  if (fd_ < 0) throw WriteError(path_, std::strerror(errno));
}

CheckedFile::CheckedFile(CheckedFile&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), path_(std::move(other.path_)) {}

CheckedFile& CheckedFile::operator=(CheckedFile&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
    path_ = std::move(other.path_);
  }
  return *this;
}

CheckedFile::~CheckedFile() {
  if (fd_ >= 0) ::close(fd_);
}

void CheckedFile::write(std::string_view text) {
  if (fd_ < 0) return;
  const std::size_t allowed = allowed_by_hook(path_, text.size());
  std::size_t done = 0;
  while (done < allowed) {
    const ssize_t n = ::write(fd_, text.data() + done, allowed - done);
    if (n < 0) {
      if (errno == EINTR) continue;  // a signal (Ctrl-C) during the write: finish it
      throw WriteError(path_, std::strerror(errno));
    }
    done += static_cast<std::size_t>(n);
  }
  if (allowed < text.size()) throw WriteError(path_, std::strerror(ENOSPC));
}

void CheckedFile::close() {
  if (fd_ < 0) return;
  const int fd = std::exchange(fd_, -1);
  if (::close(fd) != 0 && errno != EINTR) throw WriteError(path_, std::strerror(errno));
}

}  // namespace poise::studies
