/// WideColumnsWriter (wide_columns.h): samples.h5 created, its chunks written as the rows come
/// (or the rows kept in memory only), closed with its values digest.
#include <hdf5.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_pipeline.h>
#include <zlib.h>

#include <algorithm>
#include <boost/uuid/detail/sha1.hpp>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/format.h"
#include "engine/results/checked_file.h"
#include "engine/results/chunk_codec.h"
#include "engine/results/hdf5_handles.h"
#include "engine/results/wide_columns.h"
#include "engine/run/thread_arena.h"

namespace poise::engine {
namespace {

using Sha1 = boost::uuids::detail::sha1;
using hdf5::Id;
using hdf5::number_attribute;
using hdf5::text_attribute;

std::string hex(const Sha1::digest_type& d) {
  std::string hex;
  for (const auto word : d) hex += fmt::format("{:08x}", word);  // five 32-bit words
  return hex;
}

// A chunked, deflated, growable dataset of `rank` dimensions (the first unlimited).
Id growable(hid_t file, const std::string& name, hid_t type, hsize_t columns, hsize_t chunk_rows, bool shuffle) {
  const int rank = columns > 0 ? 2 : 1;
  const hsize_t dims[2] = {0, columns}, maxdims[2] = {H5S_UNLIMITED, columns}, chunk[2] = {chunk_rows, 1};
  Id space(H5Screate_simple(rank, dims, maxdims), H5Sclose);
  Id dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_chunk(dcpl.get(), rank, chunk);
  if (shuffle) H5Pset_shuffle(dcpl.get());
  H5Pset_deflate(dcpl.get(), static_cast<unsigned>(kChunkDeflateLevel));
  if (type == H5T_IEEE_F32LE) {
    const float fill = NAN;
    H5Pset_fill_value(dcpl.get(), H5T_NATIVE_FLOAT, &fill);
  }
  Id d(H5Dcreate2(file, name.c_str(), type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), H5Dclose);
  if (!d.ok()) throw Error(hdf5::failed("cannot create dataset /" + name));
  return d;
}

// Appends `n` values of a 1-D growable dataset at row `first`.
void append_rows(hid_t dset, hid_t mem_type, hsize_t first, hsize_t n, const void* data) {
  const hsize_t size = first + n;
  if (H5Dset_extent(dset, &size) < 0) throw Error(hdf5::failed("cannot grow a dataset"));
  Id file_space(H5Dget_space(dset), H5Sclose);
  H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, &first, nullptr, &n, nullptr);
  Id mem_space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  if (H5Dwrite(dset, mem_type, mem_space.get(), file_space.get(), H5P_DEFAULT, data) < 0) {
    throw Error(hdf5::failed("cannot write rows"));
  }
}

// Floats from one column's start to the next in a column-major block: the rows and one cache
// line more. At a stride of exactly 16384 floats (64 KiB) the 16 columns a row is transposed
// into all fall in the same set of the L1 and L2 caches, and every store misses.
std::size_t padded_stride(std::size_t rows) { return rows + 64 / sizeof(float); }

// Columns per block of a flush: as wide as a cache line.
constexpr std::size_t kBlock = 64 / sizeof(float);

}  // namespace

struct WideColumnsWriter::Handles {
  Id file, values, sample, ok;
};

// One flush's blocks of columns: the rows, the encoded chunks, the per-thread buffers and
// the first failed chunk write (the blocks after it are dropped).
struct WideColumnsWriter::FlushBlocks {
  std::size_t r = 0;                                                  // rows in the chunk
  hsize_t first = 0;                                                  // the chunk's first row in the dataset
  const float* rows = nullptr;                                        // [row][column], when not kept
  std::vector<std::uint64_t> samples;                                 // the rows' sample indices
  std::vector<std::uint8_t> ok;                                       // and ok flags
  std::size_t blocks = 0, next_block = 0;                             // of columns; the next to encode (spread)
  std::vector<std::string> encoded;                                   // per column
  tbb::enumerable_thread_specific<std::vector<float>> block_columns;  // one block's columns per thread
  tbb::enumerable_thread_specific<std::vector<float>> padded;         // a kept partial column, padded
  std::string write_error;
};

WideColumnsWriter::WideColumnsWriter(std::string path, WideColumnsSpec spec, std::size_t planned_rows,
                                     const std::map<std::string, std::string>& text_attributes,
                                     const std::map<std::string, std::uint64_t>& number_attributes, int threads)
    : path_(std::move(path)),
      spec_(std::move(spec)),
      chunk_rows_(std::clamp<std::size_t>(planned_rows, 1, kWideChunkRows)),
      threads_(std::max(1, threads)),
      planned_rows_(std::max<std::size_t>(planned_rows, 1)),
      crc_(spec_.columns, static_cast<std::uint32_t>(crc32(0L, Z_NULL, 0))) {
  hdf5::quiet();
  require(spec_.columns > 0, "samples.h5: a wide dataset needs at least one column");
  const bool keep = fits_in_memory(spec_, planned_rows_);
  require(keep || !path_.empty(), "wide columns kept in memory only need " +
                                      std::to_string(planned_rows_ * spec_.columns * sizeof(float)) +
                                      " bytes, more than the " + std::to_string(spec_.keep_up_to_bytes) + " allowed");
  if (!path_.empty()) {
    h_ = std::make_unique<Handles>();
    try {
      h_->file = Id(H5Fcreate(path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, hdf5::unlocked_access()), H5Fclose);
      if (!h_->file.ok()) throw Error(hdf5::failed("HDF5 cannot create the file"));
      const hid_t f = h_->file.get();
      for (const auto& [k, v] : text_attributes) text_attribute(f, k, v);
      for (const auto& [k, v] : number_attributes) number_attribute(f, k, v);
      const auto rows = static_cast<hsize_t>(chunk_rows_);
      h_->sample = growable(f, "sample", H5T_STD_U64LE, 0, rows, false);
      text_attribute(h_->sample.get(), "description", "sample index of each row");
      h_->ok = growable(f, "ok", H5T_STD_U8LE, 0, rows, false);
      text_attribute(h_->ok.get(), "description", "1 = the sample succeeded, 0 = it failed (its values are NaN)");
      h_->values = growable(f, spec_.dataset, H5T_IEEE_F32LE, static_cast<hsize_t>(spec_.columns), rows, true);
      text_attribute(h_->values.get(), "units", spec_.unit);
      text_attribute(h_->values.get(), "description", spec_.description);
      for (const auto& c : spec_.coordinates) {
        require(c.values.size() == spec_.columns, "samples.h5: coordinate " + c.name + " has the wrong length");
        const hsize_t n = c.values.size();
        Id space(H5Screate_simple(1, &n, nullptr), H5Sclose);
        Id d(H5Dcreate2(f, c.name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
             H5Dclose);
        if (!d.ok() || H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, c.values.data()) < 0) {
          throw Error(hdf5::failed("cannot write /" + c.name));
        }
        text_attribute(d.get(), "units", c.unit);
        text_attribute(d.get(), "description", c.description);
      }
    } catch (const Error& e) {
      h_.reset();
      throw WriteError(path_, e.what());
    }
  }
  // Not zeroed: each row is written before it is read, and its pages are first touched by
  // append, on the thread that gathers samples while the others compute. Kept columns take
  // the rows directly (a row's values go to 169 cache lines that the next 15 rows fill up):
  // no row buffer, no transposition.
  if (keep) {
    kept_ = LargeBuffer<float>(padded_stride(planned_rows_) * spec_.columns);
  } else {
    buffer_ = LargeBuffer<float>(chunk_rows_ * spec_.columns);
  }
  samples_.reserve(chunk_rows_);
  ok_.reserve(chunk_rows_);
}

std::span<const float> WideColumnsWriter::kept_column(std::size_t p) const {
  require(keeps() && p < spec_.columns, "wide columns: column " + std::to_string(p) + " is not kept");
  return {kept_.data() + p * padded_stride(planned_rows_), rows_written_};
}

WideColumnsWriter::~WideColumnsWriter() {
  if (closed_) return;
  try {
    close();
  } catch (const std::exception&) {  // a destructor does not throw: the run reports its own error
  }
}

void WideColumnsWriter::append(std::size_t sample, bool ok, std::span<const float> values) {
  require(!closed_, "samples.h5: append after close");
  require(sample == rows_written_ + samples_.size(), "samples.h5: rows must come in sample order");
  require(rows_written_ + samples_.size() < planned_rows_ || !keeps(), "wide columns: more rows than planned");
  require(!ok || values.size() == spec_.columns, "samples.h5: a row has the wrong number of values");
  const std::size_t r = samples_.size();
  if (keeps()) {
    const std::size_t stride = padded_stride(planned_rows_);
    float* at = kept_.data() + rows_written_ + r;
    for (std::size_t k = 0; k < spec_.columns; ++k) at[k * stride] = ok ? values[k] : NAN;
  } else {
    float* row = buffer_.data() + r * spec_.columns;
    if (ok) {
      std::copy(values.begin(), values.end(), row);
    } else {
      std::fill(row, row + spec_.columns, NAN);
    }
  }
  samples_.push_back(sample);
  ok_.push_back(ok ? 1 : 0);
  if (spread_) advance_spread_flush(spread_->blocks * samples_.size() / chunk_rows_);  // its blocks due by now
  if (samples_.size() == chunk_rows_) flush();
}

// Block b's columns (kBlock wide): taken from the kept columns, or transposed row by row from
// the row buffer into the thread's block buffer; their CRCs updated, and each encoded.
void WideColumnsWriter::encode_block(std::size_t b, FlushBlocks& f) {
  const std::size_t r = f.r, g = spec_.columns;
  const hsize_t first = f.first;
  const std::size_t p0 = b * kBlock, width = std::min(kBlock, g - p0);
  float* base = nullptr;  // column k of the block at base + k * stride
  std::size_t stride = 0;
  if (keeps()) {  // the rows are in their columns already
    stride = padded_stride(planned_rows_);
    base = kept_.data() + p0 * stride + first;
  } else {
    std::vector<float>& columns = f.block_columns.local();
    stride = padded_stride(chunk_rows_);
    columns.resize(width * stride);
    base = columns.data();
    for (std::size_t i = 0; i < r; ++i) {
      const float* row = f.rows + i * g + p0;
      for (std::size_t k = 0; k < width; ++k) base[k * stride + i] = row[k];
    }
  }
  for (std::size_t k = 0; k < width; ++k) {
    const std::size_t p = p0 + k;
    float* values = base + k * stride;
    crc_[p] = static_cast<std::uint32_t>(
        crc32(crc_[p], reinterpret_cast<const Bytef*>(values), static_cast<uInt>(r * sizeof(float))));
    if (!h_) continue;
    if (r < chunk_rows_ && keeps()) {  // the kept rows end at r: pad a copy
      std::vector<float>& pad = f.padded.local();
      pad.assign(chunk_rows_, 0.0f);
      std::copy(values, values + r, pad.begin());
      values = pad.data();
    } else if (r < chunk_rows_) {
      std::fill(values + r, values + chunk_rows_, 0.0f);
    }
    const std::span<const float> column(values, chunk_rows_);
    if (spec_.compress) {
      f.encoded[p] = encode_chunk(column, kChunkDeflateLevel, r);
    } else {
      f.encoded[p].assign(reinterpret_cast<const char*>(column.data()), column.size() * sizeof(float));
    }
  }
}

// Block b's encoded chunks written in order (HDF5 calls are serialized), each freed at once.
void WideColumnsWriter::write_block(std::size_t b, FlushBlocks& f) const {
  if (!h_) return;
  const std::size_t g = spec_.columns;
  const std::size_t p0 = b * kBlock, width = std::min(kBlock, g - p0);
  for (std::size_t p = p0; p < p0 + width && f.write_error.empty(); ++p) {
    const hsize_t offset[2] = {f.first, p};
    const std::uint32_t skipped = spec_.compress ? 0u : 3u;  // bit 0 shuffle, bit 1 deflate
    if (H5Dwrite_chunk(h_->values.get(), H5P_DEFAULT, skipped, offset, f.encoded[p].size(), f.encoded[p].data()) < 0) {
      f.write_error = hdf5::failed("cannot write a chunk of /" + spec_.dataset);
    }
    std::string().swap(f.encoded[p]);  // written: its memory goes back at once
  }
}

// The buffered rows as one flush: the dataset grown to hold them, their sample indices and ok
// flags handed over, the buffer empty again.
std::unique_ptr<WideColumnsWriter::FlushBlocks> WideColumnsWriter::start_flush() {
  auto f = std::make_unique<FlushBlocks>();
  f->r = samples_.size();
  f->first = rows_written_;
  f->blocks = (spec_.columns + kBlock - 1) / kBlock;
  f->encoded.resize(spec_.columns);
  const hsize_t extent[2] = {f->first + f->r, spec_.columns};
  if (h_ && H5Dset_extent(h_->values.get(), extent) < 0) {
    throw WriteError(path_, hdf5::failed("cannot grow /" + spec_.dataset));
  }
  f->samples.swap(samples_);
  f->ok.swap(ok_);
  samples_.reserve(chunk_rows_);
  ok_.reserve(chunk_rows_);
  rows_written_ += f->r;
  return f;
}

// After a flush's last block: its first failed write, else its sample indices and ok flags.
void WideColumnsWriter::finish_flush(FlushBlocks& f) {
  if (!f.write_error.empty()) throw WriteError(path_, f.write_error);
  if (!h_) return;
  try {
    append_rows(h_->sample.get(), H5T_NATIVE_UINT64, f.first, f.r, f.samples.data());
    append_rows(h_->ok.get(), H5T_NATIVE_UINT8, f.first, f.r, f.ok.data());
  } catch (const Error& e) {
    throw WriteError(path_, e.what());
  }
}

// The spread flush's blocks up to `blocks_due` encoded and written, on this thread; finished
// after its last.
void WideColumnsWriter::advance_spread_flush(std::size_t blocks_due) {
  FlushBlocks& f = *spread_;
  for (; f.next_block < std::min(blocks_due, f.blocks); ++f.next_block) {
    encode_block(f.next_block, f);
    write_block(f.next_block, f);
  }
  if (f.next_block < f.blocks) return;
  const std::unique_ptr<FlushBlocks> done = std::move(spread_);
  finish_flush(*done);
}

void WideColumnsWriter::flush() {
  if (spread_) advance_spread_flush(spread_->blocks);  // a chunk row's columns in order
  if (samples_.empty()) return;
  // Spread: the full row buffer is swapped for a second one and compressed while the rows
  // after it come in (append). Else a pipeline on the run's threads: blocks of columns as
  // wide as a cache line are taken from the kept columns, or transposed row by row from the
  // row buffer into a block buffer per thread, and encoded in parallel, and written in order
  // by one stage at a time (HDF5 calls are serialized) while later blocks are still being
  // encoded. The rows past r of a last, partial chunk are outside the dataset: zeros compress
  // best.
  const bool spread = spec_.spread_compression && !closed_;
  if (spread && !keeps()) {
    if (spread_rows_.size() == 0) spread_rows_ = LargeBuffer<float>(chunk_rows_ * spec_.columns);
    std::swap(buffer_, spread_rows_);
  }
  std::unique_ptr<FlushBlocks> f = start_flush();
  if (!keeps()) f->rows = spread ? spread_rows_.data() : buffer_.data();
  if (spread) {
    spread_ = std::move(f);
    return;
  }
  const std::size_t blocks = f->blocks;
  std::size_t next_block = 0;
  run_on_threads(threads_, [&] {
    tbb::parallel_pipeline(2 * static_cast<std::size_t>(threads_) + 1,
                           tbb::make_filter<void, std::size_t>(tbb::filter_mode::serial_in_order,
                                                               [&](tbb::flow_control& fc) -> std::size_t {
                                                                 if (next_block == blocks) fc.stop();
                                                                 return next_block++;
                                                               }) &
                               tbb::make_filter<std::size_t, std::size_t>(tbb::filter_mode::parallel,
                                                                          [&](std::size_t b) {
                                                                            encode_block(b, *f);
                                                                            return b;
                                                                          }) &
                               tbb::make_filter<std::size_t, void>(tbb::filter_mode::serial_in_order,
                                                                   [&](std::size_t b) { write_block(b, *f); }));
  });
  finish_flush(*f);
}

nlohmann::json WideColumnsWriter::close() {
  if (closed_) return nullptr;
  closed_ = true;
  flush();
  Sha1 all;
  for (const std::uint32_t c : crc_) {
    const unsigned char bytes[4] = {static_cast<unsigned char>(c >> 24), static_cast<unsigned char>(c >> 16),
                                    static_cast<unsigned char>(c >> 8), static_cast<unsigned char>(c)};
    all.process_bytes(bytes, sizeof bytes);
  }
  Sha1::digest_type total;
  all.get_digest(total);
  if (!h_) return nullptr;  // no file
  // Closing a dataset writes what HDF5 still caches of it: a full disk can show here first.
  const bool datasets_closed = h_->values.reset() >= 0 && h_->sample.reset() >= 0 && h_->ok.reset() >= 0;
  if (!datasets_closed || H5Fflush(h_->file.get(), H5F_SCOPE_GLOBAL) < 0 || h_->file.reset() < 0) {
    throw WriteError(path_, hdf5::failed("HDF5 could not flush and close the file"));
  }
  return {{"file", std::filesystem::path(path_).filename().string()},
          {"dataset", spec_.dataset},
          {"rows", rows_written_},
          {"columns", spec_.columns},
          {"unit", spec_.unit},
          {"values_digest", hex(total)},
          {"values_digest_is", "SHA-1 of the CRC-32s of each column's little-endian float32 values, in column order"}};
}

}  // namespace poise::engine
