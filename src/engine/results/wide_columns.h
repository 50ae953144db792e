#pragma once
/// samples.h5: the wide per-sample results of a run (a value at every grid point of every
/// sample), beside samples.csv, which keeps the inputs and scalar outputs people open in a
/// spreadsheet. HDF5 (Debian's serial libhdf5), readable by h5py and pandas:
///   /sample        uint64 [rows]            sample index of each row (rows are samples 0, 1, ...)
///   /ok            uint8  [rows]            1 = the sample succeeded, 0 = it failed (values NaN)
///   /<dataset>     float32 [rows, columns]  chunks of up to 16384 rows x 1 column (a column,
///                                           e.g. one grid point over all samples, reads alone),
///                                           byte shuffle + deflate; attributes "units",
///                                           "description"
///   /<coordinate>  float64 [columns]        what each column is (e.g. yaw_deg), attribute "units"
///   root attributes: whatever the run gives (study, kind, seed, planned samples, version).
/// The writer keeps one chunk row (16384 rows x columns values) in memory, whatever the
/// sample count; or, when every planned row fits in `keep_up_to_bytes` (fits_in_memory), all
/// rows column by column instead (kept_column: field statistics then never read the file back
/// or inflate it). Chunks are compressed on all the run's threads (chunk_codec.h) and written
/// by HDF5's direct chunk write. A column's values are digested as they are written:
/// values_digest = SHA-1 of the concatenated CRC-32s (zlib's, 4 bytes big-endian) of each
/// column's little-endian float32 values in sample order, so equal data give equal digests
/// whatever the file bytes (CRC-32 runs at memory speed; SHA-1 of the values would cost more
/// than the compression).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/large_buffer.h"

namespace poise::engine {

/// What one column of the wide dataset is, e.g. {"yaw_deg", "deg", ..., one value per column}.
struct ColumnCoordinate {
  std::string name, unit, description;
  std::vector<double> values;
};

struct WideColumnsSpec {
  std::string dataset;  ///< e.g. "grid_total_arcsec"
  std::string unit;     ///< e.g. "arcsec"
  std::string description;
  std::size_t columns = 0;
  std::vector<ColumnCoordinate> coordinates;
  /// false: chunks stored raw, with HDF5's per-chunk mask saying both filters were skipped
  /// (a scratch file read back at once and removed: compression would only cost time).
  bool compress = true;
  /// All rows are also kept in memory, column by column, when the planned rows' values take at
  /// most this many bytes (kKeepColumnsBytes for a run's file; 0 = never). A writer with no
  /// file (an empty path) keeps them only there and needs them to fit.
  std::size_t keep_up_to_bytes = 0;
  /// Compress a full chunk row a block of columns at a time while the next chunk row comes in,
  /// evenly over its rows, on the appending thread, instead
  /// of all at once on the run's threads: appending then costs about the same for every row.
  /// For an MPI run's rank 0, whose share of the samples is balanced on its cost of writing them
  /// (engine/run/sample_driver.h). The file is the same.
  bool spread_compression = false;
};

/// What a run keeps in memory of its wide values at most: 256 MiB, 397,000 samples of a
/// 169-point grid. A run planned larger streams them from its file (memory independent of the
/// sample count); below it the copy saves reading back and inflating every chunk twice.
inline constexpr std::size_t kKeepColumnsBytes = std::size_t{256} << 20;

/// Whether `rows` rows of `spec` fit in spec.keep_up_to_bytes: a WideColumnsWriter planned for
/// them keeps them in memory.
inline bool fits_in_memory(const WideColumnsSpec& spec, std::size_t rows) {
  const std::size_t values_per_row = std::max<std::size_t>(spec.columns, 1);
  return std::max<std::size_t>(rows, 1) <= spec.keep_up_to_bytes / sizeof(float) / values_per_row;
}

/// Rows per chunk of samples.h5 (fewer when the run plans fewer samples).
inline constexpr std::size_t kWideChunkRows = 16384;

class WideColumnsWriter {
 public:
  /// Creates `path` (replacing any file there) for at most `planned_rows` rows. Root
  /// attributes: strings and unsigned integers. Throws WriteError if HDF5 cannot create it.
  /// An empty path writes no file: the rows are only kept in memory (spec.keep_up_to_bytes
  /// must hold them all, else poise::Error).
  WideColumnsWriter(std::string path, WideColumnsSpec spec, std::size_t planned_rows,
                    const std::map<std::string, std::string>& text_attributes,
                    const std::map<std::string, std::uint64_t>& number_attributes, int threads);
  ~WideColumnsWriter();
  WideColumnsWriter(const WideColumnsWriter&) = delete;
  WideColumnsWriter& operator=(const WideColumnsWriter&) = delete;

  /// Appends the next sample's row (its index must be the row number); a failed sample's
  /// values are stored as NaN.
  void append(std::size_t sample, bool ok, std::span<const float> values);
  /// Writes what is buffered and closes the file. Returns {"file", "dataset", "rows",
  /// "columns", "unit", "values_digest"} for summary.json. Throws WriteError on failure.
  nlohmann::json close();
  const std::string& path() const { return path_; }
  /// Whether all rows are kept in memory (the planned rows fit in spec.keep_up_to_bytes).
  bool keeps() const { return kept_.size() != 0; }
  /// Column p's values of every row appended so far (after close: of the whole run); only
  /// when keeps().
  std::span<const float> kept_column(std::size_t p) const;

 private:
  void flush();
  struct FlushBlocks;  // one flush's blocks of columns (wide_columns_writer.cc)
  std::unique_ptr<FlushBlocks> start_flush();
  void finish_flush(FlushBlocks& f);
  void advance_spread_flush(std::size_t blocks_due);
  void encode_block(std::size_t b, FlushBlocks& f);
  void write_block(std::size_t b, FlushBlocks& f) const;
  struct Handles;
  std::string path_;
  WideColumnsSpec spec_;
  std::size_t chunk_rows_;
  int threads_;
  std::unique_ptr<Handles> h_;  ///< null: no file
  std::size_t planned_rows_;
  LargeBuffer<float> buffer_;           ///< [row in chunk][column], chunk_rows_ rows; when not kept
  LargeBuffer<float> kept_;             ///< [column][row], planned_rows_ rows, when kept
  std::vector<std::uint64_t> samples_;  ///< rows in the buffer
  std::vector<std::uint8_t> ok_;
  std::size_t rows_written_ = 0;         ///< rows before the buffer's (a spread flush's included)
  std::unique_ptr<FlushBlocks> spread_;  ///< the chunk row a spread flush is compressing
  LargeBuffer<float> spread_rows_;       ///< its rows, when not kept (the buffer swapped in)
  std::vector<std::uint32_t> crc_;       ///< per column, of the values so far
  bool closed_ = false;
};

/// Reads the wide dataset of a samples.h5 column by column. read_column may be called from
/// several threads at once: HDF5 calls are serialized, decompression runs in the caller.
class WideColumnsReader {
 public:
  /// Throws poise::Error naming the file if it or the dataset cannot be opened.
  WideColumnsReader(std::string path, const std::string& dataset);
  ~WideColumnsReader();
  WideColumnsReader(const WideColumnsReader&) = delete;
  WideColumnsReader& operator=(const WideColumnsReader&) = delete;

  std::size_t rows() const { return rows_; }
  std::size_t columns() const { return columns_; }
  /// Every row's value of column p (NaN for failed samples).
  void read_column(std::size_t p, std::vector<float>& out) const;
  /// Rows [first, first + n) of every column, row by row (out: n x columns()); reads each chunk
  /// they touch once.
  void read_rows(std::size_t first, std::size_t n, std::vector<float>& out) const;
  /// The /sample and /ok datasets.
  std::vector<std::uint64_t> sample_index() const;
  std::vector<std::uint8_t> ok() const;

 private:
  /// The chunk of column p that starts at row `first`, decoded (all NaN where never written).
  void read_chunk(std::size_t first, std::size_t p, std::vector<float>& chunk, std::string& stored) const;
  struct Handles;
  std::string path_;
  std::unique_ptr<Handles> h_;
  std::size_t rows_ = 0, columns_ = 0, chunk_rows_ = 0;
  mutable std::mutex hdf5_;
};

}  // namespace poise::engine
