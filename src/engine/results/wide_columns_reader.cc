/// WideColumnsReader (wide_columns.h): a samples.h5 read back column by column, each chunk
/// read under a lock and decompressed by the calling thread.
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <mutex>

#include "core/error.h"
#include "engine/results/chunk_codec.h"
#include "engine/results/hdf5_handles.h"
#include "engine/results/wide_columns.h"

namespace poise::engine {

using hdf5::Id;

struct WideColumnsReader::Handles {
  Id file, values;
};

WideColumnsReader::WideColumnsReader(std::string path, const std::string& dataset)
    : path_(std::move(path)), h_(std::make_unique<Handles>()) {
  hdf5::quiet();
  h_->file = Id(H5Fopen(path_.c_str(), H5F_ACC_RDONLY, hdf5::unlocked_access()), H5Fclose);
  if (!h_->file.ok()) throw Error(path_ + ": not an HDF5 file HDF5 can open");
  h_->values = Id(H5Dopen2(h_->file.get(), dataset.c_str(), H5P_DEFAULT), H5Dclose);
  if (!h_->values.ok()) throw Error(path_ + ": no dataset /" + dataset);
  Id space(H5Dget_space(h_->values.get()), H5Sclose);
  hsize_t dims[2] = {0, 0};
  if (H5Sget_simple_extent_ndims(space.get()) != 2 || H5Sget_simple_extent_dims(space.get(), dims, nullptr) < 0) {
    throw Error(path_ + ": /" + dataset + " is not a [rows, columns] table");
  }
  rows_ = dims[0];
  columns_ = dims[1];
  Id dcpl(H5Dget_create_plist(h_->values.get()), H5Pclose);
  hsize_t chunk[2] = {0, 0};
  if (H5Pget_layout(dcpl.get()) != H5D_CHUNKED || H5Pget_chunk(dcpl.get(), 2, chunk) != 2 || chunk[1] != 1) {
    throw Error(path_ + ": /" + dataset + " is not stored in chunks of one column");
  }
  chunk_rows_ = chunk[0];
}

WideColumnsReader::~WideColumnsReader() = default;

void WideColumnsReader::read_chunk(std::size_t first, std::size_t p, std::vector<float>& chunk,
                                   std::string& stored) const {
  chunk.resize(chunk_rows_);
  std::uint32_t mask = 0;
  {
    const std::lock_guard<std::mutex> lock(hdf5_);
    const hsize_t offset[2] = {first, p};
    hsize_t size = 0;
    if (H5Dget_chunk_storage_size(h_->values.get(), offset, &size) < 0) {
      throw Error(path_ + ": cannot locate the chunk at row " + std::to_string(first));
    }
    stored.resize(size);
    if (size > 0 && H5Dread_chunk(h_->values.get(), H5P_DEFAULT, offset, &mask, stored.data()) < 0) {
      throw Error(hdf5::failed(path_ + ": cannot read the chunk at row " + std::to_string(first)));
    }
  }
  if (stored.empty()) {  // never written: the fill value
    std::fill(chunk.begin(), chunk.end(), NAN);
    return;
  }
  decode_chunk(stored, mask, chunk, path_);
}

void WideColumnsReader::read_column(std::size_t p, std::vector<float>& out) const {
  POISE_INVARIANT(p < columns_, path_ + ": column " + std::to_string(p) + " is past the last");
  out.resize(rows_);
  std::vector<float> chunk;
  std::string stored;
  for (std::size_t first = 0; first < rows_; first += chunk_rows_) {
    read_chunk(first, p, chunk, stored);
    const std::size_t n = std::min(chunk_rows_, rows_ - first);
    std::copy(chunk.begin(), chunk.begin() + static_cast<long>(n), out.begin() + static_cast<long>(first));
  }
}

void WideColumnsReader::read_rows(std::size_t first, std::size_t n, std::vector<float>& out) const {
  POISE_INVARIANT(first + n <= rows_, path_ + ": rows " + std::to_string(first) + " to " + std::to_string(first + n) +
                                          " are past the last");
  out.resize(n * columns_);
  std::vector<float> chunk;
  std::string stored;
  for (std::size_t start = first - first % chunk_rows_; start < first + n; start += chunk_rows_) {
    const std::size_t from = std::max(start, first), to = std::min(start + chunk_rows_, first + n);
    for (std::size_t p = 0; p < columns_; ++p) {
      read_chunk(start, p, chunk, stored);
      for (std::size_t row = from; row < to; ++row) out[(row - first) * columns_ + p] = chunk[row - start];
    }
  }
}

namespace {
template <class T>
std::vector<T> read_1d(hid_t file, const std::string& path, const char* name, hid_t mem_type) {
  Id d(H5Dopen2(file, name, H5P_DEFAULT), H5Dclose);
  if (!d.ok()) throw Error(path + ": no dataset /" + name);
  Id space(H5Dget_space(d.get()), H5Sclose);
  hsize_t n = 0;
  H5Sget_simple_extent_dims(space.get(), &n, nullptr);
  std::vector<T> v(n);
  if (n > 0 && H5Dread(d.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0) {
    throw Error(path + ": cannot read /" + name);
  }
  return v;
}
}  // namespace

std::vector<std::uint64_t> WideColumnsReader::sample_index() const {
  const std::lock_guard<std::mutex> lock(hdf5_);
  return read_1d<std::uint64_t>(h_->file.get(), path_, "sample", H5T_NATIVE_UINT64);
}

std::vector<std::uint8_t> WideColumnsReader::ok() const {
  const std::lock_guard<std::mutex> lock(hdf5_);
  return read_1d<std::uint8_t>(h_->file.get(), path_, "ok", H5T_NATIVE_UINT8);
}

}  // namespace poise::engine
