// samples.h5 (engine/results/wide_columns.h): what Poise writes with its own chunk filters is what
// the HDF5 library itself reads (h5py, pandas read through it), column by column and whole.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <zlib.h>

#include <boost/uuid/detail/sha1.hpp>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <vector>

#include "core/error.h"
#include "engine/results/checked_file.h"
#include "engine/results/chunk_codec.h"
#include "engine/results/wide_columns.h"
#include "test_util.h"

namespace poise {
namespace {

using engine::WideColumnsReader;
using engine::WideColumnsSpec;
using engine::WideColumnsWriter;

// Rows [rows][columns]; every 10th sample failed.
std::vector<std::vector<float>> make_rows(std::size_t rows, std::size_t columns) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 40.0f);
  std::vector<std::vector<float>> out(rows, std::vector<float>(columns));
  for (auto& r : out) {
    for (auto& v : r) v = u(rng);
  }
  return out;
}

WideColumnsSpec spec(std::size_t columns) {
  WideColumnsSpec s{"grid_total_arcsec", "arcsec", "test field", columns, {}};
  engine::ColumnCoordinate c{"grid_yaw_deg", "deg", "yaw", {}};
  for (std::size_t p = 0; p < columns; ++p) c.values.push_back(-30.0 + 5.0 * static_cast<double>(p));
  s.coordinates = {c};
  return s;
}

std::string write(const std::string& path, const std::vector<std::vector<float>>& rows, std::size_t planned) {
  WideColumnsWriter w(path, spec(rows[0].size()), planned, {{"study", "unit test"}}, {{"seed", 42}}, 2);
  for (std::size_t i = 0; i < rows.size(); ++i) w.append(i, i % 10 != 9, rows[i]);
  return w.close()["values_digest"].get<std::string>();
}

// The SHA-1 of the concatenated CRC-32s of each column's float32 values, computed here from
// the rows as a reader of the file would (zlib.crc32 and hashlib in the README do the same).
std::string expected_digest(const std::vector<std::vector<float>>& rows) {
  using Sha1 = boost::uuids::detail::sha1;
  Sha1 all;
  for (std::size_t p = 0; p < rows[0].size(); ++p) {
    std::vector<float> column;
    for (std::size_t i = 0; i < rows.size(); ++i) column.push_back(i % 10 != 9 ? rows[i][p] : NAN);
    const auto crc = static_cast<std::uint32_t>(
        crc32(0L, reinterpret_cast<const Bytef*>(column.data()), static_cast<uInt>(column.size() * sizeof(float))));
    const unsigned char b[4] = {static_cast<unsigned char>(crc >> 24), static_cast<unsigned char>(crc >> 16),
                                static_cast<unsigned char>(crc >> 8), static_cast<unsigned char>(crc)};
    all.process_bytes(b, 4);
  }
  Sha1::digest_type d;
  all.get_digest(d);
  char buf[41];
  for (int i = 0; i < 5; ++i) std::snprintf(buf + 8 * i, 9, "%08x", d[i]);
  return buf;
}

TEST(WideColumns, ColumnsReadBackExactlyAcrossChunks) {
  test::TempDir d;
  const std::size_t rows = 2 * engine::kWideChunkRows + 123, columns = 5;  // two whole chunks and a partial one
  const auto data = make_rows(rows, columns);
  const std::string digest = write(d.file("s.h5"), data, rows + 1000);
  EXPECT_EQ(digest, expected_digest(data));
  const WideColumnsReader r(d.file("s.h5"), "grid_total_arcsec");
  ASSERT_EQ(r.rows(), rows);
  ASSERT_EQ(r.columns(), columns);
  std::vector<float> col;
  for (std::size_t p = 0; p < columns; ++p) {
    r.read_column(p, col);
    ASSERT_EQ(col.size(), rows);
    for (std::size_t i = 0; i < rows; ++i) {
      if (i % 10 == 9) {
        EXPECT_TRUE(std::isnan(col[i])) << i;
      } else {
        ASSERT_EQ(col[i], data[i][p]) << "row " << i << " column " << p;
      }
    }
  }
  const auto index = r.sample_index();
  const auto ok = r.ok();
  ASSERT_EQ(index.size(), rows);
  EXPECT_EQ(index[rows - 1], rows - 1);
  EXPECT_EQ(ok[9], 0);
  EXPECT_EQ(ok[10], 1);
}

TEST(WideColumns, KeptColumnsEqualWhatTheFileHolds) {
  test::TempDir d;
  const std::size_t rows = 2 * engine::kWideChunkRows + 123, columns = 5, planned = rows + 1000;
  const auto data = make_rows(rows, columns);
  WideColumnsSpec kept = spec(columns);
  kept.keep_up_to_bytes = planned * columns * sizeof(float);
  auto fill = [&](WideColumnsWriter& w) {
    for (std::size_t i = 0; i < rows; ++i) w.append(i, i % 10 != 9, data[i]);
  };
  WideColumnsWriter with_file(d.file("kept.h5"), kept, planned, {}, {}, 2);
  ASSERT_TRUE(with_file.keeps());
  fill(with_file);
  EXPECT_EQ(with_file.close()["values_digest"].get<std::string>(), expected_digest(data));
  WideColumnsWriter memory_only("", kept, planned, {}, {}, 2);  // no file at all
  fill(memory_only);
  EXPECT_TRUE(memory_only.close().is_null());
  const WideColumnsReader r(d.file("kept.h5"), "grid_total_arcsec");
  std::vector<float> col;
  for (std::size_t p = 0; p < columns; ++p) {
    r.read_column(p, col);
    for (const WideColumnsWriter* w : {&with_file, &memory_only}) {
      const auto k = w->kept_column(p);
      ASSERT_EQ(k.size(), rows);
      EXPECT_EQ(std::memcmp(k.data(), col.data(), rows * sizeof(float)), 0) << "column " << p;  // NaN too
    }
  }
  // A kept writer holds no more rows than planned; one without a file needs them to fit.
  WideColumnsWriter small(d.file("small.h5"), kept, 3, {}, {}, 1);
  for (std::size_t i = 0; i < 3; ++i) small.append(i, true, data[i]);
  EXPECT_THROW(small.append(3, true, data[3]), Error);
  WideColumnsSpec tight = spec(columns);
  tight.keep_up_to_bytes = 100;
  EXPECT_THROW(WideColumnsWriter("", tight, 1000, {}, {}, 1), Error);
  WideColumnsWriter streams(d.file("streams.h5"), tight, 1000, {}, {}, 1);
  EXPECT_FALSE(streams.keeps());
}

// An MPI run's rank 0 compresses each full chunk row over the next one's appends
// (spread_compression): the file, its digest and the kept columns are those of a writer that
// compresses each at once, also when the run ends with a spread chunk row still in flight.
TEST(WideColumns, SpreadCompressionWritesTheSameColumns) {
  test::TempDir d;
  const std::size_t columns = 40;  // three blocks of columns
  for (const std::size_t rows : {2 * engine::kWideChunkRows + 123, engine::kWideChunkRows + 9000}) {
    const auto data = make_rows(rows, columns);
    for (const bool kept : {false, true}) {
      WideColumnsSpec at_once = spec(columns);
      at_once.keep_up_to_bytes = kept ? (rows + 10) * columns * sizeof(float) : 0;
      WideColumnsSpec spread = at_once;
      spread.spread_compression = true;
      WideColumnsWriter a(d.file("at_once.h5"), at_once, rows + 10, {}, {}, 2);
      WideColumnsWriter b(d.file("spread.h5"), spread, rows + 10, {}, {}, 1);
      ASSERT_EQ(b.keeps(), kept);
      for (std::size_t i = 0; i < rows; ++i) {
        a.append(i, i % 10 != 9, data[i]);
        b.append(i, i % 10 != 9, data[i]);
      }
      const auto digest = b.close()["values_digest"].get<std::string>();
      EXPECT_EQ(digest, a.close()["values_digest"].get<std::string>());
      EXPECT_EQ(digest, expected_digest(data));
      const WideColumnsReader ra(d.file("at_once.h5"), "grid_total_arcsec");
      const WideColumnsReader rb(d.file("spread.h5"), "grid_total_arcsec");
      ASSERT_EQ(rb.rows(), rows);
      EXPECT_EQ(rb.sample_index(), ra.sample_index());
      EXPECT_EQ(rb.ok(), ra.ok());
      std::vector<float> ca, cb;
      for (std::size_t p = 0; p < columns; ++p) {
        ra.read_column(p, ca);
        rb.read_column(p, cb);
        ASSERT_EQ(cb.size(), rows);
        EXPECT_EQ(std::memcmp(ca.data(), cb.data(), rows * sizeof(float)), 0) << "column " << p;
        if (kept) {
          EXPECT_EQ(std::memcmp(b.kept_column(p).data(), cb.data(), rows * sizeof(float)), 0);
        }
      }
    }
  }
}

TEST(WideColumns, TheHdf5LibraryReadsWhatPoiseCompressed) {
  test::TempDir d;
  const std::size_t rows = 3000, columns = 7;
  const auto data = make_rows(rows, columns);
  write(d.file("s.h5"), data, rows);
  // Through HDF5's own filter pipeline (shuffle + deflate), as h5py would.
  const hid_t f = H5Fopen(d.file("s.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t ds = H5Dopen2(f, "grid_total_arcsec", H5P_DEFAULT);
  ASSERT_GE(ds, 0);
  std::vector<float> all(rows * columns);
  ASSERT_GE(H5Dread(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, all.data()), 0);
  for (std::size_t i = 0; i < rows; ++i) {
    for (std::size_t p = 0; p < columns; ++p) {
      if (i % 10 == 9) {
        EXPECT_TRUE(std::isnan(all[i * columns + p]));
      } else {
        ASSERT_EQ(all[i * columns + p], data[i][p]) << i << "," << p;
      }
    }
  }
  // The filters are declared, so any reader knows them; the unit is an attribute.
  const hid_t dcpl = H5Dget_create_plist(ds);
  EXPECT_EQ(H5Pget_nfilters(dcpl), 2);
  unsigned flags = 0;
  std::size_t nelmts = 0;
  EXPECT_EQ(H5Pget_filter2(dcpl, 0, &flags, &nelmts, nullptr, 0, nullptr, nullptr), H5Z_FILTER_SHUFFLE);
  nelmts = 1;
  unsigned level = 0;
  EXPECT_EQ(H5Pget_filter2(dcpl, 1, &flags, &nelmts, &level, 0, nullptr, nullptr), H5Z_FILTER_DEFLATE);
  H5Pclose(dcpl);
  const hid_t a = H5Aopen(ds, "units", H5P_DEFAULT);
  ASSERT_GE(a, 0);
  const hid_t t = H5Aget_type(a);
  char* units = nullptr;
  ASSERT_GE(H5Aread(a, t, &units), 0);
  EXPECT_STREQ(units, "arcsec");
  H5free_memory(units);
  H5Tclose(t);
  H5Aclose(a);
  H5Dclose(ds);
  H5Fclose(f);
}

TEST(WideColumns, UncompressedScratchChunksReadBackThroughBothReaders) {
  test::TempDir d;
  const auto data = make_rows(500, 3);
  WideColumnsSpec raw = spec(3);
  raw.compress = false;
  {
    WideColumnsWriter w(d.file("raw.h5"), raw, 500, {}, {}, 2);
    for (std::size_t i = 0; i < data.size(); ++i) w.append(i, i % 10 != 9, data[i]);
    EXPECT_EQ(w.close()["values_digest"], expected_digest(data));  // the digest is of the values
  }
  {
    const WideColumnsReader r(d.file("raw.h5"), "grid_total_arcsec");
    std::vector<float> col;
    r.read_column(2, col);
    EXPECT_EQ(col[0], data[0][2]);
    EXPECT_EQ(col[498], data[498][2]);
  }  // closed: HDF5 refuses a second open of a file with other access properties
  const hid_t f = H5Fopen(d.file("raw.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t ds = H5Dopen2(f, "grid_total_arcsec", H5P_DEFAULT);
  std::vector<float> all(500 * 3);
  ASSERT_GE(H5Dread(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, all.data()), 0);
  EXPECT_EQ(all[3 * 7 + 1], data[7][1]);
  H5Dclose(ds);
  H5Fclose(f);
}

TEST(WideColumns, ChunkCodecRoundTripAndDamage) {
  std::vector<float> v(1000);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = 0.001f * static_cast<float>(i * i);
  const std::string z = engine::encode_chunk(v);
  EXPECT_LT(z.size(), v.size() * sizeof(float));
  std::vector<float> back(v.size());
  engine::decode_chunk(z, 0, back, "x.h5");
  EXPECT_EQ(back, v);
  std::string bad = z.substr(0, z.size() / 2);
  try {
    engine::decode_chunk(bad, 0, back, "x.h5");
    FAIL() << "a cut chunk was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("x.h5: a chunk does not inflate"), std::string::npos) << e.what();
  }
}

// Noisy values: the low mantissa byte planes are near 8 bits of entropy and go into stored
// blocks, the sign-and-exponent plane is Huffman-coded, all in one zlib stream.
TEST(WideColumns, ChunkCodecStoresNoisyPlanesAndCodesTheRest) {
  std::mt19937_64 rng(3);
  std::lognormal_distribution<double> d(1.0, 0.5);
  std::vector<float> v(16384);
  for (float& f : v) f = static_cast<float>(d(rng));
  const std::string z = engine::encode_chunk(v);
  EXPECT_LT(z.size(), v.size() * sizeof(float));                       // the exponent plane shrank
  EXPECT_GT(z.size(), 3 * v.size());                                    // three planes kept whole
  std::vector<float> back(v.size());
  engine::decode_chunk(z, 0, back, "x.h5");
  EXPECT_EQ(0, std::memcmp(back.data(), v.data(), v.size() * sizeof(float)));
  // Any zlib reader: zlib's own uncompress, as HDF5's deflate filter uses it.
  std::vector<unsigned char> plain(v.size() * sizeof(float));
  uLongf size = static_cast<uLongf>(plain.size());
  ASSERT_EQ(Z_OK, uncompress(plain.data(), &size, reinterpret_cast<const Bytef*>(z.data()), static_cast<uLong>(z.size())));
  EXPECT_EQ(size, plain.size());
  // A constant column: every plane is coded (entropy 0; Huffman coding alone spends at least
  // one bit per byte, so at best an eighth of the raw bytes), and it still decodes.
  const std::vector<float> flat(4096, 2.5f);
  const std::string zf = engine::encode_chunk(flat);
  EXPECT_LT(zf.size(), flat.size() * sizeof(float) / 4);
  std::vector<float> flat_back(flat.size());
  engine::decode_chunk(zf, 0, flat_back, "x.h5");
  EXPECT_EQ(flat_back, flat);
  // A last chunk, its 6784 data rows noisy and the rest zeros: its planes are judged by the
  // data rows, so the low mantissa planes' data bytes are stored, as in a full chunk, and the
  // zeros after them coded as runs (a few bytes); it decodes to the same values.
  const std::size_t rows = 6784;
  std::vector<float> last(v.begin(), v.end());
  std::fill(last.begin() + rows, last.end(), 0.0f);
  const std::string by_data = engine::encode_chunk(last, engine::kChunkDeflateLevel, rows);
  EXPECT_GT(by_data.size(), 2 * rows);  // two planes' data kept whole
  const std::string data_alone = engine::encode_chunk(std::span<const float>(last.data(), rows));
  EXPECT_LT(by_data.size(), data_alone.size() + 200);             // the zeros cost next to nothing
  EXPECT_LE(by_data.size(), engine::encode_chunk(last).size());  // no larger than coded with the padding
  std::vector<float> last_back(last.size());
  engine::decode_chunk(by_data, 0, last_back, "x.h5");
  EXPECT_EQ(0, std::memcmp(last_back.data(), last.data(), last.size() * sizeof(float)));
}

// A device that accepts no byte (/dev/full: every write fails with ENOSPC, as on a full disk):
// the error names the file and gives the system's reason.
TEST(WideColumns, AFullDiskGivesTheSystemsReason) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this system";
  try {
    WideColumnsWriter w("/dev/full", spec(3), 100, {{"study", "x"}}, {}, 1);
    const float row[3] = {1.0f, 2.0f, 3.0f};
    for (std::size_t i = 0; i < 100; ++i) w.append(i, true, row);
    w.close();
    FAIL() << "writing to /dev/full succeeded";
  } catch (const engine::WriteError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("/dev/full"), std::string::npos) << what;
    EXPECT_NE(what.find("No space left on device"), std::string::npos) << what;
  }
}

TEST(WideColumns, RowsOutOfOrderAndUnwritableFilesAreRefused) {
  test::TempDir d;
  WideColumnsWriter w(d.file("s.h5"), spec(2), 10, {}, {}, 1);
  const float row[2] = {1.0f, 2.0f};
  w.append(0, true, row);
  EXPECT_THROW(w.append(2, true, row), Error);
  w.close();
  try {
    WideColumnsWriter bad(d.file("no_such_folder/s.h5"), spec(2), 10, {}, {}, 1);
    FAIL() << "a file in a missing folder was created";
  } catch (const engine::WriteError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_folder/s.h5"), std::string::npos) << e.what();
  }
  EXPECT_THROW(WideColumnsReader(d.file("s.h5"), "no_dataset"), Error);
}

}  // namespace
}  // namespace poise
