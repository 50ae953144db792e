#include "engine/chunk_codec.h"

#include <zlib.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "core/error.h"

namespace poise::studies {
namespace {

constexpr std::size_t kElement = sizeof(float);

void shuffle(const unsigned char* in, unsigned char* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < kElement; ++j) out[j * n + i] = in[i * kElement + j];
  }
}

void unshuffle(const unsigned char* in, unsigned char* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < kElement; ++j) out[i * kElement + j] = in[j * n + i];
  }
}

// Bytes a Huffman code of this plane's byte frequencies needs, at best (its entropy).
double entropy_bytes(const unsigned char* plane, std::size_t n) {
  std::size_t counts[256] = {};
  for (std::size_t i = 0; i < n; ++i) ++counts[plane[i]];
  double bits = 0.0;
  const double nn = static_cast<double>(n);
  for (std::size_t c : counts) {
    if (c != 0) bits -= static_cast<double>(c) * std::log2(static_cast<double>(c) / nn);
  }
  return bits / 8.0;
}

}  // namespace

std::string encode_chunk(std::span<const float> values, int level) {
  const std::size_t n = values.size();
  const std::size_t bytes = n * kElement;
  std::vector<unsigned char> shuffled(bytes);
  shuffle(reinterpret_cast<const unsigned char*>(values.data()), shuffled.data(), n);
  z_stream z{};
  int rc = deflateInit2(&z, level, Z_DEFLATED, 15, 8, Z_HUFFMAN_ONLY);
  require(rc == Z_OK, "samples.h5: zlib could not start (code " + std::to_string(rc) + ")");
  // Room for Huffman blocks no larger than stored ones (zlib falls back to stored blocks)
  // and the 5-byte header of each stored block of at most 65535 bytes.
  std::string out(deflateBound(&z, static_cast<uLong>(bytes)) + 5 * (bytes / 16384 + kElement) + 64, '\0');
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  bool huffman = true;
  for (std::size_t j = 0; j < kElement && rc == Z_OK; ++j) {
    unsigned char* plane = shuffled.data() + j * n;
    const bool worth_it = entropy_bytes(plane, n) < kStoredAbove * static_cast<double>(n);
    if (worth_it != huffman) {
      huffman = worth_it;
      rc = deflateParams(&z, huffman ? level : 0, huffman ? Z_HUFFMAN_ONLY : Z_DEFAULT_STRATEGY);
      if (rc != Z_OK) break;
    }
    z.next_in = plane;
    z.avail_in = static_cast<uInt>(n);
    rc = deflate(&z, j + 1 == kElement ? Z_FINISH : Z_NO_FLUSH);
    if (j + 1 < kElement && rc == Z_OK && z.avail_in != 0) rc = Z_BUF_ERROR;
  }
  const std::size_t size = z.total_out;
  deflateEnd(&z);
  require(rc == Z_STREAM_END, "samples.h5: zlib could not compress a chunk (code " + std::to_string(rc) + ")");
  return std::string(out.data(), size);  // exactly its size: 169 of them wait for the write
}

void decode_chunk(std::string_view stored, std::uint32_t filter_mask, std::span<float> out, const std::string& what) {
  const std::size_t bytes = out.size() * kElement;
  const bool shuffled = (filter_mask & 1u) == 0;
  const bool deflated = (filter_mask & 2u) == 0;
  std::vector<unsigned char> plain(bytes);
  if (deflated) {
    uLongf size = static_cast<uLongf>(bytes);
    const int rc = uncompress(plain.data(), &size, reinterpret_cast<const Bytef*>(stored.data()),
                              static_cast<uLong>(stored.size()));
    if (rc != Z_OK || size != bytes) {
      throw Error(what + ": a chunk does not inflate to " + std::to_string(bytes) + " bytes (zlib code " +
                  std::to_string(rc) + "): the file is damaged");
    }
  } else {
    if (stored.size() != bytes) throw Error(what + ": a stored chunk has " + std::to_string(stored.size()) +
                                            " bytes, expected " + std::to_string(bytes));
    std::memcpy(plain.data(), stored.data(), bytes);
  }
  if (shuffled) {
    unshuffle(plain.data(), reinterpret_cast<unsigned char*>(out.data()), out.size());
  } else {
    std::memcpy(out.data(), plain.data(), bytes);
  }
}

}  // namespace poise::studies
