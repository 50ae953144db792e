#pragma once
/// Result files written with every write checked: the first write the system refuses (a
/// full disk, a quota, an I/O error) throws a WriteError naming the file and the system's
/// reason ("…/samples.csv: No space left on device"), so a run stops at once instead of
/// computing on into a file that no longer grows.
///
/// Test hook (injected: engine/results/fault_injection.h, fail_writes_after): the checked
/// writes of this process fail with ENOSPC once N bytes in all have been written through them
/// (a disk that fills up mid-run), the last one short as a real full disk's; optionally only
/// the writes of files of one name (e.g. samples.csv) count and fail. The `poise` command sets
/// it from POISE_INJECT_WRITE_FAILURE_AFTER=N and POISE_INJECT_WRITE_FAILURE_FILE=NAME.
#include <string>
#include <string_view>

#include "core/error.h"

namespace poise::engine {

/// A write the system refused. path() is the file; what() reads "<path>: <reason>".
class WriteError : public Error {
 public:
  WriteError(std::string path, const std::string& reason);
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// A file opened for writing (new, truncated, or appended to); every write is checked and
/// reaches the system before write() returns (no user-space buffer to lose).
class CheckedFile {
 public:
  CheckedFile() = default;                     ///< closed: writes nothing (MPI ranks other than 0)
  CheckedFile(std::string path, bool append);  ///< throws WriteError if it cannot be opened
  CheckedFile(CheckedFile&& other) noexcept;
  CheckedFile& operator=(CheckedFile&& other) noexcept;
  CheckedFile(const CheckedFile&) = delete;
  CheckedFile& operator=(const CheckedFile&) = delete;
  ~CheckedFile();

  bool is_open() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }
  /// Writes all of `text` or throws WriteError (a full disk: after what fit).
  void write(std::string_view text);
  /// Closes the file; a failure the system reports only at close throws WriteError.
  void close();

 private:
  int fd_ = -1;
  std::string path_;
};

}  // namespace poise::engine
