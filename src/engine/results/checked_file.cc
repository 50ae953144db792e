#include "engine/results/checked_file.h"

#include "engine/results/fault_injection.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <utility>

namespace poise::engine {

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
  const std::size_t allowed = fault_injection::allowed_write(path_, text.size());
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

}  // namespace poise::engine
