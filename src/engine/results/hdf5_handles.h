#pragma once
/// What Poise's HDF5 writer and reader (wide_columns.h) share: an HDF5 identifier closed when it
/// goes out of scope, HDF5's own error printing switched off, the system's reason for a failure
/// taken from HDF5's error stack, and file access without HDF5's file locks.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <utility>

namespace poise::engine::hdf5 {

/// An HDF5 identifier closed by its own close function when it goes out of scope.
class Id {
 public:
  Id() = default;
  Id(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Id(Id&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = -1; }
  Id& operator=(Id&& o) noexcept {
    std::swap(id_, o.id_);
    std::swap(close_, o.close_);
    return *this;
  }
  Id(const Id&) = delete;
  Id& operator=(const Id&) = delete;
  ~Id() { reset(); }
  herr_t reset() {
    herr_t rc = 0;
    if (id_ >= 0 && close_) rc = close_(id_);
    id_ = -1;
    return rc;
  }
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }

 private:
  hid_t id_ = -1;
  herr_t (*close_)(hid_t) = nullptr;
};

/// Switches off HDF5's printing of its error stack (once per process): Poise reports its own.
void quiet();

/// The operating system's reason for HDF5's last failure on this thread, from its error stack:
/// the file driver records "errno = 28, error message = 'No space left on device'" when a read
/// or write fails. "" when the failure was not the system's.
std::string system_reason();

/// `what` failed: with the system's reason when HDF5 recorded one.
std::string failed(const std::string& what);

/// A UTF-8 string attribute and an unsigned 64-bit attribute of an HDF5 object. Throw
/// poise::Error with the system's reason when HDF5 cannot write them.
void text_attribute(hid_t obj, const std::string& name, const std::string& value);
void number_attribute(hid_t obj, const std::string& name, std::uint64_t value);

/// File access without HDF5's file locks: one process writes the file (rank 0), and the
/// locks fail on file systems that lack them (NFS, Lustre of a cluster).
hid_t unlocked_access();

}  // namespace poise::engine::hdf5
